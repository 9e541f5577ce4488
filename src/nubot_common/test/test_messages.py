"""The package's messages and services: generated classes match the chapter, every field documents itself."""

import importlib
import re
from pathlib import Path

import pytest

import nubot_common.msg as msgs
import nubot_common.srv as srvs

PACKAGE_DIR = Path(__file__).resolve().parents[1]
MSG_FILES = sorted((PACKAGE_DIR / "msg").glob("*.msg"))
SRV_FILES = sorted((PACKAGE_DIR / "srv").glob("*.srv"))

# The chapter's definitions: name -> [(type, field), ...] in declaration order.
CHAPTER_MESSAGES = {
    "VelCmd": [("float32", "Vx"), ("float32", "Vy"), ("float32", "w")],
    "Point2d": [("float32", "x"), ("float32", "y")],
    "PPoint": [("float32", "angle"), ("float32", "radius")],
    "Angle": [("float32", "theta")],
    "BallInfo": [
        ("std_msgs/Header", "header"),
        ("int32", "ballinfostate"),
        ("nubot_common/Point2d", "pos"),
        ("nubot_common/PPoint", "real_pos"),
        ("nubot_common/Point2d", "velocity"),
        ("bool", "pos_known"),
        ("bool", "velocity_known"),
    ],
    "ObstaclesInfo": [
        ("std_msgs/Header", "header"),
        ("nubot_common/Point2d[]", "pos"),
        ("nubot_common/PPoint[]", "polar_pos"),
    ],
    "RobotInfo": [
        ("std_msgs/Header", "header"),
        ("int32", "AgentID"),
        ("int32", "targetNum1"),
        ("int32", "targetNum2"),
        ("int32", "targetNum3"),
        ("int32", "targetNum4"),
        ("int32", "staticpassNum"),
        ("int32", "staticcatchNum"),
        ("nubot_common/Point2d", "pos"),
        ("nubot_common/Angle", "heading"),
        ("float32", "vrot"),
        ("nubot_common/Point2d", "vtrans"),
        ("bool", "iskick"),
        ("bool", "isvalid"),
        ("bool", "isstuck"),
        ("bool", "isdribble"),
        ("char", "current_role"),
        ("float32", "role_time"),
        ("nubot_common/Point2d", "target"),
    ],
    "OmniVisionInfo": [
        ("std_msgs/Header", "header"),
        ("nubot_common/BallInfo", "ballinfo"),
        ("nubot_common/ObstaclesInfo", "obstacleinfo"),
        ("nubot_common/RobotInfo[]", "robotinfo"),
    ],
    "CoachInfo": [
        ("std_msgs/Header", "header"),
        ("char", "MatchMode"),
        ("char", "MatchType"),
        ("char", "TestMode"),
        ("nubot_common/Point2d", "pointA"),
        ("nubot_common/Point2d", "pointB"),
        ("int16", "angleA"),
        ("int16", "angleB"),
        ("char", "idA"),
        ("char", "idB"),
        ("char", "kickforce"),
    ],
}

# The chapter's services: name -> (request fields, response fields).
CHAPTER_SERVICES = {
    "BallHandle": ([("int64", "enable")], [("int64", "BallIsHolding")]),
    "Shoot": ([("int64", "strength"), ("int64", "ShootPos")], [("int64", "ShootIsDone")]),
}

# Files whose field lines need no comment: relayed Gazebo-style types and the strategy bundle.
UNCOMMENTED_FILES = {"ModelStates.msg", "ModelState.msg", "SetModelState.srv", "simulation_strategy.msg"}


def fields_of(message_class) -> list[tuple[str, str]]:
    return list(zip(message_class._slot_types, message_class.__slots__))


@pytest.mark.parametrize("name", sorted(CHAPTER_MESSAGES))
def test_chapter_message_has_the_chapter_fields_and_types(name):
    message_class = getattr(msgs, name)
    assert message_class._type == f"nubot_common/{name}"
    assert fields_of(message_class) == CHAPTER_MESSAGES[name]


@pytest.mark.parametrize("name", sorted(CHAPTER_SERVICES))
def test_chapter_service_has_the_chapter_request_and_response(name):
    service = getattr(srvs, name)
    request, response = CHAPTER_SERVICES[name]
    assert service._type == f"nubot_common/{name}"
    assert service._request_class is getattr(srvs, f"{name}Request")
    assert service._response_class is getattr(srvs, f"{name}Response")
    assert fields_of(service._request_class) == request
    assert fields_of(service._response_class) == response


@pytest.mark.parametrize("path", MSG_FILES, ids=lambda p: p.name)
def test_every_message_file_is_generated_and_importable(path):
    module = importlib.import_module(f"nubot_common.msg._{path.stem}")
    message_class = getattr(module, path.stem)
    assert message_class is getattr(msgs, path.stem)
    assert [name for _type, name in declared_fields(path.read_text())] == list(message_class.__slots__)


@pytest.mark.parametrize("path", SRV_FILES, ids=lambda p: p.name)
def test_every_service_file_is_generated_and_importable(path):
    module = importlib.import_module(f"nubot_common.srv._{path.stem}")
    assert getattr(module, path.stem) is getattr(srvs, path.stem)
    request_text, response_text = path.read_text().split("\n---\n")
    assert [n for _t, n in declared_fields(request_text)] == list(getattr(srvs, f"{path.stem}Request").__slots__)
    assert [n for _t, n in declared_fields(response_text)] == list(getattr(srvs, f"{path.stem}Response").__slots__)


def test_messages_serialize_and_deserialize():
    from io import BytesIO

    original = msgs.OmniVisionInfo()
    original.ballinfo.pos.x = 1.5
    original.ballinfo.pos_known = True
    robot = msgs.RobotInfo(AgentID=3, current_role=2)
    robot.heading.theta = -0.5
    original.robotinfo.append(robot)
    buffer = BytesIO()
    original.serialize(buffer)
    decoded = msgs.OmniVisionInfo().deserialize(buffer.getvalue())
    assert decoded.ballinfo.pos.x == 1.5
    assert decoded.ballinfo.pos_known
    assert [(r.AgentID, r.current_role, r.heading.theta) for r in decoded.robotinfo] == [(3, 2, -0.5)]


FIELD_LINE = re.compile(r"^\s*(?P<type>[A-Za-z][\w/]*(?:\[\d*\])?)\s+(?P<name>[A-Za-z]\w*)(?P<rest>.*)$")


def declared_fields(text: str) -> list[tuple[str, str]]:
    """(type, name) of every field line of a .msg text or one half of a .srv text."""
    result = []
    for line in text.splitlines():
        code = line.split("#", 1)[0].strip()
        if not code or code == "---":
            continue
        match = FIELD_LINE.match(code)
        assert match, f"cannot parse field line {line!r}"
        if "=" not in match["rest"]:
            result.append((match["type"], match["name"]))
    return result


def test_declared_fields_parser_skips_comments_separators_and_constants():
    text = "# title\nint32 a  # [m]\n\n---\nstring[] b\nint8 C=1\n   # more\n"
    assert declared_fields(text) == [("int32", "a"), ("string[]", "b")]


@pytest.mark.parametrize(
    "path", [p for p in MSG_FILES + SRV_FILES if p.name not in UNCOMMENTED_FILES], ids=lambda p: p.name
)
def test_every_field_line_has_a_comment(path):
    missing = []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        code = line.split("#", 1)[0].strip()
        if not code or code == "---" or code.split()[0] in ("Header", "std_msgs/Header"):
            continue
        if "#" not in line or not line.split("#", 1)[1].strip():
            missing.append(f"{path.name}:{number}: {line.strip()}")
    assert not missing, "field lines without a comment (unit/frame):\n" + "\n".join(missing)
