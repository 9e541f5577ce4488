"""The ball's flight between the world model and control (BallFlightInfo): round trips and what is refused."""

import io
import math

import pytest

from nubot_common import conversions as conv
from nubot_common.msg import BallFlightInfo
from nubot_common.percepts import Ball3dPercept
from nubot_common.world_state import BallFlight

# Values a float32 holds exactly (Point2d and Point3d are float32), stamps whole nanoseconds.
LOB = BallFlight(Ball3dPercept(12.5, -3.25, 1.5, 1.125, -4.5, 0.25, 2.75, True), (-5.5, 1.875, 13.0625))


def _wire(msg: BallFlightInfo) -> BallFlightInfo:
    buffer = io.BytesIO()
    msg.serialize(buffer)
    return BallFlightInfo().deserialize(buffer.getvalue())


@pytest.mark.parametrize("flight", [
    LOB,
    BallFlight(Ball3dPercept(12.5, 1.0, 2.0, 0.125, -1.0, 0.5, 0.0, True)),  # rolling: no touchdown
    BallFlight(Ball3dPercept(12.5, 1.0, 2.0, 0.125)),  # velocity not known yet
], ids=["lob", "rolling", "no-velocity"])
def test_a_flight_round_trips_exactly(flight):
    msg = _wire(conv.ball_flight_msg(flight, 12.53125))
    assert msg.header.stamp.to_sec() == 12.53125 and msg.ball.pos_known_3d and msg.in_air == flight.in_air
    assert conv.ball_flight(msg) == flight
    assert conv.ball_flight_msg(conv.ball_flight(msg), 12.53125) == msg


def test_the_touchdown_time_keeps_the_sim_time_to_the_microsecond():
    late = BallFlight(LOB.ball, (-5.5, 1.875, 1234.567891))
    back = conv.ball_flight(_wire(conv.ball_flight_msg(late, 1234.0)))
    assert back is not None and back.touchdown is not None
    assert back.touchdown[2] == pytest.approx(1234.567891, abs=1e-6), "float64: a float32 would be 0.1 ms off"


def test_no_flight_is_a_message_with_no_3d_ball_stamped_at_the_snapshot():
    msg = _wire(conv.ball_flight_msg(None, 7.5))
    assert (msg.header.stamp.to_sec(), msg.ball.header.stamp.to_sec()) == (7.5, 7.5)
    assert not (msg.ball.pos_known_3d or msg.in_air)
    assert conv.ball_flight(msg) is None


def test_a_touchdown_that_is_not_finite_reads_as_a_ball_on_the_ground():
    msg = conv.ball_flight_msg(LOB, 12.5)
    msg.touchdown_time = math.nan
    assert conv.ball_flight(msg) == BallFlight(LOB.ball)
    msg.ball.pos.z = math.inf
    assert conv.ball_flight(msg) is None
