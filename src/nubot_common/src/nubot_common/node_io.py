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

``starting_node`` starts a node (``rospy.init_node``) and holds SIGINT and SIGTERM back while it sets itself up.
rospy's own handler for them runs in the main thread and tells the master that the node goes, through the one
lock-guarded connection to the master: arriving while the main thread is itself in a call to the master (a
parameter, a registration, dynamic_reconfigure's set-up), it waits for that call's lock, which its own thread holds,
forever. A node stopped while it started (a test, Ctrl-C at once) hung until roslaunch killed it 15 s later. Held,
the signal is handled the moment the set-up is done, by rospy's handler as usual. So a set-up must not wait for
others (a service, a first message): that waits after the block, where Ctrl-C can end it.
"""

from __future__ import annotations

import signal
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import rospy

_STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def starting_node(name: str, **init_node_args: Any) -> Iterator[None]:
    """``rospy.init_node(name, **init_node_args)``, then the block (the node's set-up) with SIGINT and SIGTERM held
    back; after it, rospy's handlers for them, and a signal that came meanwhile is handled then (see the module's
    notes). A block that raises (e.g. SystemExit on bad parameters) ends the process as it would have."""
    pending: list[int] = []
    previous = {sig: signal.signal(sig, lambda number, _frame: pending.append(number)) for sig in _STOP_SIGNALS}
    try:
        rospy.init_node(name, disable_signals=True, **init_node_args)
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    rospy.core.register_signals()  # what init_node does without disable_signals
    if pending:
        signal.raise_signal(pending[0])


def publisher(topic: str, msg_type: type, latch: bool = False, queue_size: int | None = None) -> rospy.Publisher:
    """A rospy publisher that writes from the caller's thread (``queue_size=None``, documented by rospy); with a
    ``queue_size``, one that hands each message to a thread per subscriber and drops the oldest beyond it, so a
    slow subscriber never holds up the publisher (camera images: a camera drops frames nobody takes)."""
    with warnings.catch_warnings():  # rospy warns about queue_size=None whether or not it is deliberate
        warnings.simplefilter("ignore", SyntaxWarning)
        return rospy.Publisher(topic, msg_type, queue_size=queue_size, latch=latch)
