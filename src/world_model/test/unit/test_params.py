"""Unit tests of the world model's configuration (world_model.params)."""

from pathlib import Path

import pytest
import yaml

from nubot_common import NubotCommonError
from nubot_common.params import from_mapping
from world_model.params import WorldModelParams

CONFIG = Path(__file__).resolve().parents[2] / "config" / "world_model.yaml"


def test_shipped_config_holds_the_nubot_numbers():
    data = yaml.safe_load(CONFIG.read_text())
    assert data.pop("rate") == 30.0, "the node's output rate"
    params = from_mapping(WorldModelParams, data)
    assert params == WorldModelParams(), "the YAML and the defaults agree"
    assert (params.team_size, params.teammate_timeout, params.ball_timeout) == (5, 0.3, 0.3)
    assert (params.velocity_window, params.teammate_radius) == (0.5, 0.5)


@pytest.mark.parametrize(("data", "message"), [
    ({"teammate_timeout": 0.0}, "teammate_timeout must be positive, got 0.0"),
    ({"ball_timeout": -0.1}, "ball_timeout must be positive"),
    ({"velocity_window": 0}, "velocity_window must be positive"),
    ({"teammate_radius": -1.0}, "teammate_radius must be positive"),
    ({"team_size": 0}, r"team_size must lie in \[1, 99\], got 0"),
    ({"min_fit_samples": 1}, "min_fit_samples must be at least 2"),
    ({"sighting_confidence": 1.0}, r"sighting_confidence must lie in \(0, 1\)"),
    ({"teammate_timout": 0.3}, "unknown parameter.*teammate_timout"),
    ({"team_size": 2.5}, "team_size: expected an integer"),
])
def test_bad_values_are_refused_by_name(data, message):
    with pytest.raises(NubotCommonError, match=message):
        from_mapping(WorldModelParams, data, "~")
