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

``unread`` is a message type's class for a node that passes messages on without reading them (the team relay):
rospy then neither deserializes what it receives nor serializes what it sends: a relay cycle of one team (five
TeamMessages and five StrategyInfos in, two arrays of them out) took 596 us with the message classes, 14 us unread.

``yield_cpu`` lowers a node's claim on the CPU against the other nodes'. Linux shares the CPU fairly between
sessions first (autogroups), and roslaunch starts every node as a session of its own: on a machine too busy for a
whole match each node gets an equal share, so the simulator, one node, kept real time while ten robots' nodes
missed a tenth to a fifth of their cycles (a 5 vs 5 match on 2 busy cores). A simulator that yields instead slows
sim time down, and every node on sim time keeps its rate: a loaded machine slows the match, it does not change it.

``timer`` runs a node's periodic cycle. Under sim time a ``rospy.Timer`` sleeps in ``rospy.sleep``, which wakes at
every /clock message (rospy notifies every thread waiting for time to move): a 33 Hz cycle's thread woke 100 times
a second in a match, for 20 such nodes. ``timer`` instead takes /clock from the node's own /clock subscription
(rospy delivers each message once per process, to both) and wakes its thread only when a cycle is due. On wall
time (a real robot) it is a ``rospy.Timer``.
"""

from __future__ import annotations

import os
import signal
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import genpy
import rospy
from rosgraph_msgs.msg import Clock

from nubot_common import NubotCommonError
from nubot_common.conversions import model_state_msg
from nubot_common.msg import WorldModelInfo
from nubot_common.srv import SetModelState

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


_UNREAD: dict[str, type[rospy.AnyMsg]] = {}


def unread(msg_type: type[genpy.Message]) -> type[rospy.AnyMsg]:
    """A message class for ``msg_type``'s topics whose messages stay serialized, in ``._buff`` (see the module's
    notes): a subscriber of it connects only to publishers of ``msg_type`` (the same md5sum) and passes on what it
    received without deserializing it; a publisher of ``msg_type`` sends such a message's bytes as they are."""
    if msg_type._md5sum not in _UNREAD:
        _UNREAD[msg_type._md5sum] = type(f"Unread{msg_type.__name__}", (rospy.AnyMsg,), {
            "__slots__": (), "_type": msg_type._type, "_md5sum": msg_type._md5sum, "_full_text": msg_type._full_text})
    return _UNREAD[msg_type._md5sum]


def unread_message(msg_type: type[genpy.Message], data: bytes) -> rospy.AnyMsg:
    """A ``msg_type`` message already serialized into ``data``, for a publisher of ``msg_type``."""
    msg = unread(msg_type)()
    msg._buff = data
    return msg


def yield_cpu(nice: int) -> str:
    """Give this process a lower claim on the CPU, ``nice`` from 0 (none: nothing changes) to 19 (see the module's
    notes): its autogroup's nice when it leads its own session (as a node roslaunch started does) and the kernel
    groups by session, else its threads' nice (never lower than they were). Returns what it did, for the node's log;
    raises ValueError for a ``nice`` out of range."""
    if not 0 <= nice <= 19:
        raise ValueError(f"a nice value from 0 to 19, not {nice}")
    if nice == 0:
        return "the default CPU priority"
    autogroup = Path("/proc/self/autogroup")
    enabled = Path("/proc/sys/kernel/sched_autogroup_enabled")
    if os.getsid(0) == os.getpid() and autogroup.exists() and enabled.exists() and enabled.read_text().strip() == "1":
        try:
            autogroup.write_text(f"{nice}\n")
            return f"its session's CPU share at nice {nice}"
        except OSError:
            pass  # (a kernel that refuses: the threads' nice below)
    nice = max(nice, os.getpriority(os.PRIO_PROCESS, 0))  # a process started nicer stays so
    for task in os.listdir("/proc/self/task"):  # setpriority on Linux sets one thread
        try:
            os.setpriority(os.PRIO_PROCESS, int(task), max(nice, os.getpriority(os.PRIO_PROCESS, int(task))))
        except OSError:
            continue  # a thread that ended meanwhile
    return f"its threads at nice {nice}"


class _ClockTimer:
    """A periodic callback on sim time, in a thread of its own, woken by /clock only when a cycle is due.

    As ``rospy.Timer``: one cycle each period, none while the clock stands still; a cycle that ends late is followed
    at once by the ones it held up, unless it ended more than three periods after the last one was due, when the
    count starts again from then. Unlike it, the first cycle comes one period after the first /clock (not at once),
    and a clock that goes back (a simulator reset, a bag played again) starts the count again instead of ending the
    timer.
    """

    def __init__(self, period: float, callback: Callable[[rospy.timer.TimerEvent], None]):
        if not period > 0.0:
            raise ValueError(f"a timer's period must be positive, not {period} s")
        self.callback = callback
        self._period_ns = max(1, round(period * 1e9))  # in integer nanoseconds, as rospy.Time: no drift
        self._now: int | None = None  # the last /clock [ns]
        self._due: int | None = None  # when the next cycle is due [ns]; moved on by the thread after each cycle
        self._wake = threading.Event()
        self._stopped = False
        self._sub = rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=1)  # rospy's own connection
        self._thread = threading.Thread(target=self._run, name="clock_timer", daemon=True)
        self._thread.start()

    def _on_clock(self, msg: Clock) -> None:
        t, due, period = msg.clock.to_nsec(), self._due, self._period_ns
        self._now = t
        if due is None or t < due - period:  # the first tick, or the clock went back
            self._due = t + period
        elif t >= due:
            self._wake.set()

    def _run(self) -> None:
        last_expected, last_real, last_duration = None, None, None
        period = self._period_ns
        while not self._stopped and not rospy.is_shutdown():
            if not self._wake.wait(0.5):
                continue
            self._wake.clear()
            while not self._stopped and not rospy.is_shutdown():
                due, now = self._due, self._now
                if due is None or now is None or now < due:
                    break
                expected, real, start = rospy.Time(nsecs=due), rospy.Time.now(), time.monotonic()
                self.callback(rospy.timer.TimerEvent(last_expected, last_real, expected, real, last_duration))
                last_expected, last_real, last_duration = expected, real, time.monotonic() - start
                ended = self._now
                if self._due == due:  # (else the clock went back meanwhile and _on_clock set a new count)
                    self._due = ended if ended is not None and ended - (due + period) > 2 * period else due + period

    def shutdown(self) -> None:
        self._stopped = True
        self._sub.unregister()
        self._wake.set()


def timer(period: float, callback: Callable[[rospy.timer.TimerEvent], None]) -> _ClockTimer | rospy.Timer:
    """Call ``callback`` every ``period`` seconds of ROS time, in a thread of its own (see the module's notes);
    ``.shutdown()`` stops it."""
    if rospy.rostime.is_wallclock():
        return rospy.Timer(rospy.Duration(period), callback)
    return _ClockTimer(period, callback)


def wait_for_robots(names: list[str], timeout: float, stop: Callable[[], bool] = lambda: False) -> list[str]:
    """Wait until every robot publishes its world model (or ``stop()`` says so); return the ones still silent."""
    heard: set[str] = set()
    subs = [rospy.Subscriber(f"/{n}/worldmodel/worldmodelinfo", WorldModelInfo,
                             lambda _m, n=n: heard.add(n), queue_size=1) for n in names]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and len(heard) < len(names):
        if stop():
            break
        time.sleep(0.2)
    for sub in subs:
        sub.unregister()
    return sorted(set(names) - heard)


def set_model_state(name: str, x: float, y: float, z: float = 0.0, yaw: float = 0.0, timeout: float = 20.0) -> None:
    """Put the simulator's model ``name`` at rest at (x, y, z) [m], heading ``yaw`` [rad] (the simulator's
    set_model_state service, waited for up to ``timeout`` s); raise ``NubotCommonError`` with its answer if it
    refuses."""
    rospy.wait_for_service("/sim_visual/set_model_state", timeout=timeout)
    answer = rospy.ServiceProxy("/sim_visual/set_model_state", SetModelState)(model_state_msg(name, x, y, z, yaw))
    if not answer.success:
        raise NubotCommonError(f"set_model_state {name}: {answer.status_message}")
