"""The rospy plumbing every node of the workspace shares; no decision lives here.

``publisher`` makes a synchronous rospy publisher. rospy's default (``queue_size=N``) gives every subscriber
connection its own dispatch thread: each message then costs a lock, a condition notify, a ``sleep(0)`` and a
thread switch per connection. In a 5 vs 5 match that is about 20,000 thread wake-ups a second (the simulator's
/clock alone goes to some 25 nodes at 100 Hz), and on 2 cores they cost the control loops about a third of
their cycles. A synchronous publisher writes to each connection's socket from the publishing thread.

What that changes for a user: a subscriber that is alive but does not read (stopped in a debugger, SIGSTOP)
is buffered by the kernel (megabytes on loopback, a minute or more of any of our topics); past that its
publishers wait for it, as a sim-time graph waits for a paused simulator. A subscriber that dies closes its
connection and costs nothing.
"""

from __future__ import annotations

import warnings

import rospy


def publisher(topic: str, msg_type: type, latch: bool = False) -> rospy.Publisher:
    """A rospy publisher that writes from the caller's thread (``queue_size=None``, documented by rospy)."""
    with warnings.catch_warnings():  # rospy warns about queue_size=None whether or not it is deliberate
        warnings.simplefilter("ignore", SyntaxWarning)
        return rospy.Publisher(topic, msg_type, queue_size=None, latch=latch)
