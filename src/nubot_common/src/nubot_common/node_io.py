"""The rospy plumbing every node of the workspace shares; no decision lives here.

``publisher`` makes a synchronous rospy publisher. rospy's default (``queue_size=N``) gives every subscriber
connection its own dispatch thread: each message then costs a lock, a condition notify, a ``sleep(0)`` and a
thread switch per connection. A 5 vs 5 match delivers about 7,400 messages a second (``scripts/bench_match.py``;
the simulator's /clock alone goes to 28 subscribers at about 88 Hz), and on 2 cores those thread switches cost the
control loops about a third of their cycles. A synchronous publisher writes to each connection's socket from the
publishing thread.

What that changes for a user: a subscriber that is alive but does not read (stopped in a debugger, SIGSTOP)
is buffered by the kernel (about 4 MB per connection on loopback: some 30 s of model states at 100 Hz, two
minutes of WorldModelInfo at 30 Hz); past that its publishers wait for it until it reads again. A subscriber that
dies closes its connection and costs nothing.
"""

from __future__ import annotations

import warnings

import rospy


def publisher(topic: str, msg_type: type, latch: bool = False, queue_size: int | None = None) -> rospy.Publisher:
    """A rospy publisher that writes from the caller's thread (``queue_size=None``, documented by rospy); with a
    ``queue_size``, one that hands each message to a thread per subscriber and drops the oldest beyond it, so a
    slow subscriber never holds up the publisher (camera images: a camera drops frames nobody takes)."""
    with warnings.catch_warnings():  # rospy warns about queue_size=None whether or not it is deliberate
        warnings.simplefilter("ignore", SyntaxWarning)
        return rospy.Publisher(topic, msg_type, queue_size=queue_size, latch=latch)
