"""The team link of real robots: teammates' and the coach's packets over LCM (UDP multicast), as RTDB did.

Modules: ``codec`` (channels, limits, decoding and validation of the LCM packets in ``nubot_lcm``, drop
reasons), ``link`` (``TeamLink``: one team's channels over one ``lcm.LCM``, the latest packet of every
member, counters of what it dropped), ``relay`` (``TeamRelay``: the latest message of each member, younger than
an age; the simulation's relay node uses it too), ``conversions`` (ROS messages <-> packets, for the node), ``params``
(the node's parameters) and, for the tests and ``nubot_tools.bench.team_link``, ``netns`` (network namespaces
with loss and delay). None of them imports rospy.
"""


class NubotCommError(ValueError):
    """Raised for a packet that cannot be sent or a link that cannot be built (the message says why)."""
