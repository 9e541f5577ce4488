"""Tests for nubot_common.reconfigure: run-time dynamic_reconfigure config types."""

import pytest
from dynamic_reconfigure.encoding import (
    decode_config,
    decode_description,
    encode_config,
    encode_description,
    extract_params,
    get_tree,
    initial_config,
)

from nubot_common.reconfigure import ReconfigureParam, config_type

PARAMS = [
    ReconfigureParam("noise_std", "double", 0.05, 0.0, 1.0, "position noise [m]"),
    ReconfigureParam("delay_frames", "int", 2, 0, 10, "sensing delay [frames]"),
    ReconfigureParam("show_ball", "bool", True, False, True, "draw the ball"),
    ReconfigureParam("team", "str", "cyan", "", "", "team colour"),
]


def test_defaults_min_max_level_and_type_dicts():
    config = config_type(PARAMS)
    assert config.defaults == {"noise_std": 0.05, "delay_frames": 2, "show_ball": True, "team": "cyan"}
    assert config.min == {"noise_std": 0.0, "delay_frames": 0, "show_ball": False, "team": ""}
    assert config.max == {"noise_std": 1.0, "delay_frames": 10, "show_ball": True, "team": ""}
    assert config.level == {"noise_std": 0, "delay_frames": 0, "show_ball": 0, "team": 0}
    assert config.type == {"noise_std": "double", "delay_frames": "int", "show_ball": "bool", "team": "str"}
    assert config.all_level == 0


def test_description_has_one_parameter_entry_per_param_in_order():
    description = config_type(PARAMS).config_description
    entries = description["parameters"]
    assert [e["name"] for e in entries] == [p.name for p in PARAMS]
    for entry, param in zip(entries, PARAMS):
        assert entry["type"] == param.kind
        assert entry["default"] == param.default
        assert entry["min"] == param.minimum
        assert entry["max"] == param.maximum
        assert entry["description"] == param.description
        assert entry["level"] == 0
    assert [e["ctype"] for e in entries] == ["double", "int", "bool", "std::string"]
    assert description["groups"] == []
    assert (description["id"], description["parent"], description["name"]) == (0, 0, "Default")


def test_empty_parameter_list_gives_an_empty_description():
    config = config_type([])
    assert config.config_description["parameters"] == []
    assert config.defaults == {}
    assert list(encode_description(config).groups[0].parameters) == []


def test_unknown_kind_is_rejected_naming_the_param():
    with pytest.raises(ValueError, match=r"unknown parameter kind 'float' for gain"):
        ReconfigureParam("gain", "float", 1.0, 0.0, 2.0, "a gain")


def test_encode_description_accepts_the_config_type():
    message = encode_description(config_type(PARAMS))
    assert len(message.groups) == 1
    group = message.groups[0]
    assert (group.name, group.id, group.parent) == ("Default", 0, 0)
    assert [(p.name, p.type, p.level, p.description) for p in group.parameters] == [
        (p.name, p.kind, 0, p.description) for p in PARAMS
    ]
    assert {d.name: d.value for d in message.dflt.doubles} == {"noise_std": 0.05}
    assert {i.name: i.value for i in message.dflt.ints} == {"delay_frames": 2}
    assert {b.name: b.value for b in message.dflt.bools} == {"show_ball": True}
    assert {s.name: s.value for s in message.dflt.strs} == {"team": "cyan"}
    assert {i.name: i.value for i in message.max.ints} == {"delay_frames": 10}
    assert {d.name: d.value for d in message.min.doubles} == {"noise_std": 0.0}


def test_encoded_description_decodes_back_to_the_parameters():
    decoded = decode_description(encode_description(config_type(PARAMS)))
    assert [(p["name"], p["type"], p["default"], p["min"], p["max"]) for p in decoded["parameters"]] == [
        (p.name, p.kind, p.default, p.minimum, p.maximum) for p in PARAMS
    ]


def test_encode_config_round_trips_the_defaults():
    config = config_type(PARAMS)
    decoded = decode_config(encode_config(config.defaults))
    assert dict(decoded) == config.defaults


def test_the_servers_offline_setup_sequence_accepts_the_config_type():
    # dynamic_reconfigure.server.Server.__init__ without its rospy calls.
    config_class = config_type(PARAMS)
    description = encode_description(config_class)
    config = config_class.defaults.copy()
    config["groups"] = get_tree(description)
    config = initial_config(encode_config(config), config_class.config_description)
    assert {name: config[name] for name in config_class.defaults} == config_class.defaults
    assert config["groups"]["name"] == "Default"
    assert [p["name"] for p in extract_params(config_class.config_description)] == [p.name for p in PARAMS]
    request = encode_config({"noise_std": 0.2, "team": "magenta"})
    assert dict(decode_config(request, config_class.config_description)) == {"noise_std": 0.2, "team": "magenta"}


def test_an_integer_default_of_a_double_param_is_encoded_as_a_double():
    config_class = config_type([ReconfigureParam("gain", "double", 1, 0, 10, "controller gain")])
    message = encode_description(config_class)
    assert [d.name for d in message.dflt.doubles] == ["gain"]
    assert [d.name for d in message.max.doubles] == ["gain"]
