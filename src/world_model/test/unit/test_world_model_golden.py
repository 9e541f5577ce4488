"""The world model held to its golden sequences: every input and read of two robots' world models in a seeded lockstep
match, replayed in order into new world models, read the same."""

import dataclasses
import enum
import json
import lzma
import math
from pathlib import Path

import pytest

import nubot_common.field
import nubot_common.geometry
import nubot_common.match_mode
import nubot_common.percepts
import nubot_common.team_play
import nubot_common.world_description
import nubot_common.world_state
import world_model.params
from world_model.world_model import WorldModel

GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "world.jsonl.xz"
TOLERANCE = 1e-9  # [m], [m/s], [s], [rad]: the recorded reads keep 12 significant digits


def _classes() -> dict[str, type]:
    found: dict[str, type] = {}
    for module in (nubot_common.field, nubot_common.geometry, nubot_common.match_mode, nubot_common.percepts,
                   nubot_common.team_play, nubot_common.world_description, nubot_common.world_state,
                   world_model.params):
        for name, value in vars(module).items():
            if isinstance(value, type) and value.__module__ == module.__name__:
                found[name] = value
    return found


CLASSES = _classes()


def decode(tree, objects):
    """The value ``nubot_tools.golden.encode`` made ``tree`` of (``{"@": key}``: the record ``objects[key]``)."""
    if isinstance(tree, list):
        return [decode(v, objects) for v in tree]
    if not isinstance(tree, dict):
        return tree
    if "@" in tree:
        return objects[tree["@"]]
    if "_e" in tree:
        return CLASSES[tree["_e"]](tree["v"])
    if "_t" in tree:
        return tuple(decode(v, objects) for v in tree["_t"])
    if "_d" in tree:
        return {decode(k, objects): decode(v, objects) for k, v in tree["_d"]}
    if "_b" in tree:
        return tree["_b"].encode("latin-1")
    return CLASSES[tree["_"]](*(decode(v, objects) for v in tree["f"]))


def differences(got, want, where="result"):
    """Where ``got`` differs from ``want`` (numbers by more than TOLERANCE), as text; empty: the same."""
    if isinstance(want, float) and isinstance(got, (int, float)) and not isinstance(got, bool):
        same = got == want or (math.isnan(got) and math.isnan(want)) or abs(got - want) <= TOLERANCE
        return [] if same else [f"{where}: {got!r} != {want!r}"]
    if type(got) is not type(want):
        return [f"{where}: a {type(got).__name__} ({got!r}), recorded a {type(want).__name__} ({want!r})"]
    if isinstance(want, enum.Enum):
        return [] if got is want else [f"{where}: {got!r} != {want!r}"]
    if dataclasses.is_dataclass(want):
        return [d for f in dataclasses.fields(want)
                for d in differences(getattr(got, f.name), getattr(want, f.name), f"{where}.{f.name}")]
    if isinstance(want, (tuple, list)):
        if len(got) != len(want):
            return [f"{where}: {len(got)} items, recorded {len(want)}"]
        names = getattr(want, "_fields", range(len(want)))
        return [d for n, g, w in zip(names, got, want) for d in differences(g, w, f"{where}[{n}]")]
    return [] if got == want else [f"{where}: {got!r} != {want!r}"]


def test_the_world_model_reads_its_golden_sequences_the_same_way():
    """Two robots' world models (the goalie, whose RGB-D cameras see the ball in 3-D, and a teammate) over 15 s of a
    seeded lockstep match (``python -m nubot_tools.golden world``): every input replayed in order into new world
    models; every other snapshot and shared view read the same, numbers to 1e-9."""
    objects, calls = {}, []
    with lzma.open(GOLDEN, "rt", encoding="utf-8") as trace:
        for line in trace:
            record = json.loads(line)
            if "object" in record:
                objects[record["object"]] = decode(record["value"], objects)
            else:
                calls.append(record)
    models: dict[int, WorldModel] = {}
    compared = {"snapshot": 0, "own_view": 0}
    seen = {"on_ball3d": 0, "on_teammate": 0, "on_teammate_strategy": 0, "on_coach": 0, "on_vision": 0}
    for n, record in enumerate(calls):
        args = decode(record["args"], objects)
        if record["call"] == "__init__":
            models[record["robot"]] = WorldModel(*args)
            continue
        got = getattr(models[record["robot"]], record["call"])(*args)
        seen[record["call"]] = seen.get(record["call"], 0) + 1
        if record["result"] is None:
            continue
        want = decode(record["result"], objects)
        found = differences(got, want)
        assert not found, f"call {n} ({record['call']} of robot {record['robot']}): " + "; ".join(found[:5])
        if record["call"] in compared:
            compared[record["call"]] += 1
    assert len(models) == 2 and min(compared.values()) > 200, compared
    assert min(seen.values()) > 0, seen


@pytest.mark.parametrize("tree", [{"_": "NoSuchRecord", "f": []}, {"_e": "NoSuchEnum", "v": 1}])
def test_a_trace_naming_a_record_this_code_lacks_is_refused_by_name(tree):
    with pytest.raises(KeyError, match="NoSuch"):
        decode(tree, {})
