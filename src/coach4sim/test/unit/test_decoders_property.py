"""Property-based: whatever a RefBox (or a peer posing as one) or a page sends, the decoders answer with a message or
with their own error, never another exception: the RefBox stream cut into frames anywhere, its commands, the
worldstate check of the practice box, and the viewer's page messages."""

import json

from hypothesis import given, settings
from hypothesis import strategies as st

from coach4sim.refbox import (
    FrameDecoder,
    RefboxClientParams,
    RefboxError,
    map_command,
    parse_command,
    worldstate_problems,
)
from coach4sim.viewer_server import ViewerInputError, parse_page_message

JSON = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=20),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=8), inner,
                                                                                 max_size=3), max_leaves=8)
COMMAND_LIKE = st.fixed_dictionaries({}, optional={"command": JSON | st.sampled_from(["KICKOFF", "START", "STOP",
                                                                                     "GOAL", "WELCOME"]),
                                                   "targetTeam": JSON | st.just("224.16.32.53"),
                                                   "robotID": JSON})
IDENTITY = RefboxClientParams().identity


@settings(max_examples=30)  # each example is a stream of messages
@given(st.lists(st.binary(max_size=200) | st.builds(lambda m: json.dumps(m).encode() + b"\0", COMMAND_LIKE),
                max_size=6))
def test_the_refbox_stream_cut_anywhere_gives_frames_and_commands_or_their_errors(chunks):
    decoder = FrameDecoder(max_size=1000)
    for chunk in chunks:
        for frame in decoder.feed(chunk):
            assert (frame.message is None) != (frame.error == "")
            if frame.message is None:
                continue
            try:
                map_command(parse_command(frame.message), IDENTITY)
            except RefboxError:
                pass
            assert isinstance(worldstate_problems(frame.message), list)


@given(st.text(max_size=300) | st.builds(json.dumps, JSON) |
       st.builds(json.dumps, st.fixed_dictionaries({"type": st.sampled_from(["command", "watch", "replay", "x"])},
                                                   optional={"command": JSON, "team": JSON, "robot": JSON,
                                                             "action": JSON, "t": JSON, "speed": JSON})))
def test_a_page_message_is_taken_or_refused_with_the_reason(text):
    try:
        message = parse_page_message(text)
    except ViewerInputError:
        return
    assert isinstance(message, dict) and isinstance(message["type"], str)
