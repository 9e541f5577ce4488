"""Shared by the match-level tests: small teams for short matches."""

import pytest
import yaml


@pytest.fixture
def two_vs_two(tmp_path) -> list[str]:
    """``--team`` arguments of run_match.py for nubot and rival, a goalie and one field player each."""
    args = []
    for prefix, attack in (("nubot", 1), ("rival", -1)):
        path = tmp_path / f"{prefix}.yaml"
        path.write_text(yaml.safe_dump({"name": prefix.title(), "prefix": prefix, "attack": attack, "goalie": 1,
                                        "robots": [{"x": -8.4, "y": 0.0}, {"x": -1.0, "y": 0.5}]}))
        args += ["--team", str(path)]
    return args
