"""Tests for nubot_common.params: typed, validated loading of nested parameter mappings."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pytest
import yaml

from nubot_common import NubotCommonError
from nubot_common.params import from_mapping, load_yaml, to_mapping


@dataclass(frozen=True)
class PluginParams:
    x: float = 0.5
    retries: int = 3
    enabled: bool = True


@dataclass(frozen=True)
class SimParams:
    rate: float = 30.0  # [Hz]
    name: str = "world"
    plugin: PluginParams = field(default_factory=PluginParams)

    def __post_init__(self) -> None:
        if self.rate <= 0.0:
            raise ValueError(f"rate must be positive, got {self.rate}")


@dataclass(frozen=True)
class Waypoint:
    x: float = 0.0
    y: float = 0.0


@dataclass(frozen=True)
class NodeParams:
    sim: SimParams = field(default_factory=SimParams)
    gains: tuple[float, ...] = (1.0, 2.0)
    home: tuple[float, float, int] = (0.0, 0.0, 1)
    route: tuple[Waypoint, ...] = ()
    robots: int = 5


def test_empty_or_missing_mapping_gives_the_defaults():
    assert from_mapping(NodeParams, {}) == NodeParams()
    assert from_mapping(NodeParams, None) == NodeParams()


def test_nested_dataclasses_and_tuples_are_built():
    params = from_mapping(
        NodeParams,
        {
            "sim": {"rate": 100, "plugin": {"x": 2, "enabled": False}},
            "gains": [1, 2.5, 3],
            "home": [1, -2, 4],
            "route": [{"x": 1.0, "y": 2.0}, {"y": -1}],
            "robots": 2,
        },
    )
    assert params.sim == SimParams(rate=100.0, plugin=PluginParams(x=2.0, enabled=False))
    assert params.gains == (1.0, 2.5, 3.0)
    assert params.home == (1.0, -2.0, 4)
    assert params.route == (Waypoint(1.0, 2.0), Waypoint(0.0, -1.0))
    assert params.robots == 2


def test_integers_for_float_fields_become_floats():
    params = from_mapping(NodeParams, {"sim": {"rate": 10}, "gains": [1]})
    assert type(params.sim.rate) is float
    assert type(params.gains[0]) is float
    assert type(params.home[2]) is int


def test_a_dataclass_instance_is_accepted_for_a_nested_field():
    plugin = PluginParams(x=9.0)
    assert from_mapping(SimParams, {"plugin": plugin}).plugin is plugin


def test_unknown_top_level_key_is_named_with_the_known_keys():
    with pytest.raises(
        NubotCommonError,
        match=r"^NodeParams: unknown parameter\(s\) robot; " r"known: gains, home, robots, route, sim$",
    ):
        from_mapping(NodeParams, {"robot": 5})


def test_unknown_nested_key_is_named_with_its_path():
    with pytest.raises(
        NubotCommonError, match=r"^sim\.plugin: unknown parameter\(s\) retry, y; " r"known: enabled, retries, x$"
    ):
        from_mapping(NodeParams, {"sim": {"plugin": {"y": 1.0, "retry": 2}}})


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"sim": {"plugin": {"x": "fast"}}}, r"^sim\.plugin\.x: expected a number, got 'fast'$"),
        ({"sim": {"plugin": {"retries": 2.5}}}, r"^sim\.plugin\.retries: expected an integer, got 2\.5$"),
        ({"sim": {"plugin": {"enabled": 1}}}, r"^sim\.plugin\.enabled: expected true or false, got 1$"),
        ({"sim": {"name": 7}}, r"^sim\.name: expected a string, got 7$"),
        ({"sim": {"plugin": 3}}, r"^sim\.plugin: expected a mapping, got 3$"),
        ({"sim": [1, 2]}, r"^sim: expected a mapping, got \[1, 2\]$"),
        ({"gains": 1.0}, r"^gains: expected a list, got 1\.0$"),
        ({"gains": [1.0, "b"]}, r"^gains\[1\]: expected a number, got 'b'$"),
        ({"home": [1.0, 2.0]}, r"^home: expected 3 values, got 2$"),
        ({"home": [1.0, 2.0, 3.5]}, r"^home\[2\]: expected an integer, got 3\.5$"),
        ({"route": [{"x": 1.0}, {"z": 1.0}]}, r"^route\[1\]: unknown parameter\(s\) z; known: x, y$"),
        ({"route": [{"x": None}]}, r"^route\[0\]\.x: expected a number, got None$"),
    ],
)
def test_wrong_types_are_rejected_naming_the_key_path(data, message):
    with pytest.raises(NubotCommonError, match=message):
        from_mapping(NodeParams, data)


@pytest.mark.parametrize("value", [True, False])
def test_bools_are_not_accepted_as_numbers(value):
    with pytest.raises(NubotCommonError, match=rf"^sim\.plugin\.x: expected a number, got {value}$"):
        from_mapping(NodeParams, {"sim": {"plugin": {"x": value}}})
    with pytest.raises(NubotCommonError, match=rf"^robots: expected an integer, got {value}$"):
        from_mapping(NodeParams, {"robots": value})


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_non_finite_numbers_are_rejected(value):
    with pytest.raises(NubotCommonError, match=rf"^sim\.rate: expected a finite number, got {value}$"):
        from_mapping(NodeParams, {"sim": {"rate": value}})
    with pytest.raises(NubotCommonError, match=rf"^gains\[0\]: expected a finite number, got {value}$"):
        from_mapping(NodeParams, {"gains": [value]})


def test_range_errors_from_post_init_surface_as_library_errors_with_the_path():
    with pytest.raises(NubotCommonError, match=r"^sim: rate must be positive, got -1\.0$") as info:
        from_mapping(NodeParams, {"sim": {"rate": -1}})
    assert isinstance(info.value.__cause__, ValueError)
    with pytest.raises(NubotCommonError, match=r"^SimParams: rate must be positive, got 0\.0$"):
        from_mapping(SimParams, {"rate": 0})


def test_load_yaml_reads_a_file(tmp_path):
    path = tmp_path / "node.yaml"
    path.write_text(
        "sim:\n  rate: 50\n  plugin:\n    x: 1.5\ngains: [3, 4]\nroute:\n  - {x: 1, y: 2}\n", encoding="utf-8"
    )
    params = load_yaml(NodeParams, path)
    assert params == NodeParams(
        sim=SimParams(rate=50.0, plugin=PluginParams(x=1.5)), gains=(3.0, 4.0), route=(Waypoint(1.0, 2.0),)
    )
    assert load_yaml(NodeParams, str(path)) == params


def test_load_yaml_of_an_empty_file_gives_the_defaults(tmp_path):
    path = tmp_path / "empty.yaml"
    path.write_text("", encoding="utf-8")
    assert load_yaml(NodeParams, path) == NodeParams()


def test_load_yaml_names_the_file_and_the_key(tmp_path):
    path = tmp_path / "node.yaml"
    path.write_text("sim:\n  plugin:\n    x: .nan\n", encoding="utf-8")
    with pytest.raises(NubotCommonError, match=r"^node\.yaml\.sim\.plugin\.x: expected a finite number, got nan$"):
        load_yaml(NodeParams, path)
    path.write_text("robotz: 3\n", encoding="utf-8")
    with pytest.raises(NubotCommonError, match=r"^node\.yaml: unknown parameter\(s\) robotz; known: gains, "):
        load_yaml(NodeParams, path)


def test_load_yaml_of_a_missing_file_raises(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.yaml"):
        load_yaml(NodeParams, tmp_path / "missing.yaml")


def test_to_mapping_gives_plain_dicts_and_lists():
    mapping = to_mapping(NodeParams(route=(Waypoint(1.0, 2.0),)))
    assert mapping == {
        "sim": {"rate": 30.0, "name": "world", "plugin": {"x": 0.5, "retries": 3, "enabled": True}},
        "gains": [1.0, 2.0],
        "home": [0.0, 0.0, 1],
        "route": [{"x": 1.0, "y": 2.0}],
        "robots": 5,
    }


def test_to_mapping_round_trips_through_from_mapping_and_yaml(tmp_path):
    original = NodeParams(
        sim=SimParams(rate=12.5, name="pitch", plugin=PluginParams(x=-1.0, retries=0, enabled=False)),
        gains=(0.1, 0.2, 0.3),
        home=(4.0, -5.0, 2),
        route=(Waypoint(1.0, 2.0), Waypoint()),
        robots=3,
    )
    assert from_mapping(NodeParams, to_mapping(original)) == original
    path = tmp_path / "round_trip.yaml"
    path.write_text(yaml.safe_dump(to_mapping(original)), encoding="utf-8")
    assert load_yaml(NodeParams, path) == original


def test_non_string_keys_are_reported_as_unknown_parameters():
    with pytest.raises(NubotCommonError, match=r"unknown parameter\(s\) True"):
        from_mapping(NodeParams, yaml.safe_load("on: 1\n"))


@pytest.mark.parametrize("text", ["- 1\n- 2\n", "5\n"])
def test_a_top_level_value_that_is_not_a_mapping_is_rejected(tmp_path, text):
    path = tmp_path / "node.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(NubotCommonError, match=r"node\.yaml: expected a mapping"):
        load_yaml(NodeParams, path)
