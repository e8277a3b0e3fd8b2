"""actionlib's protocol core: state tables, cancel policy and goal ids, as pure data.

* :mod:`ddes.actionlib.states`: GoalStatus, CommState, SimpleGoalState; the
  server goal table (``server_goal_handle.py``), the client comm-state table
  (``action_client._transitions``) with the LOST and result rules, and
  SimpleActionClient's simple-state and ``get_state()`` mappings;
* :mod:`ddes.actionlib.cancel`: the server's status list, cancel policy,
  late-goal rule, duplicate goals and status-list expiry, as pure functions
  returning what the server publishes;
* :mod:`ddes.actionlib.goal_id`: goal ids in the server's and the client's
  formats, with a counter per generator.

On top of it, on the five topics of an action namespace:

* :class:`ActionServer` / :class:`ServerGoalHandle` (:mod:`ddes.actionlib.server`);
* :class:`ActionClient` / :class:`ClientGoalHandle` (:mod:`ddes.actionlib.client`);
* :class:`SimpleActionServer` (:mod:`ddes.actionlib.simple_server`) and
  :class:`SimpleActionClient` (:mod:`ddes.actionlib.simple_client`);
* :func:`plot_goals` (:mod:`ddes.actionlib.plot`): a timeline of goals from a trace.

They only forward what the pure functions decide.  ``docs/actionlib.md``
renders the tables and shows the servers, the clients, the protocol machine
(:mod:`ddes.testing.actions`) and the plot.
"""

from ddes.actionlib.cancel import (
    CANCELED_BY_STAMP_TEXT,
    STATUS_LIST_TIMEOUT_NS,
    UNINITIALIZED_GOAL_ID_TEXT,
    UNINITIALIZED_HANDLE_TEXT,
    CancelOutcome,
    CancelRequest,
    EventOutcome,
    GoalArrival,
    GoalOutcome,
    GoalTracker,
    Publication,
    PublicationTopic,
    ServerGoals,
    StatusOutcome,
    apply_goal_event,
    cancel_matches,
    is_expired,
    publish_status,
    receive_cancel,
    receive_goal,
)
from ddes.actionlib.client import ActionClient, ClientGoalHandle
from ddes.actionlib.goal_id import GoalIdGenerator, GoalIdStamp, GoalIdStyle
from ddes.actionlib.plot import goal_timelines, plot_goals
from ddes.actionlib.server import ActionServer, ServerGoalHandle
from ddes.actionlib.simple_client import SimpleActionClient
from ddes.actionlib.simple_server import SimpleActionServer
from ddes.actionlib.states import (
    COMM_TRANSITIONS,
    INVALID_TRANSITION,
    NO_TRANSITION,
    SERVER_STATES,
    SERVER_TRANSITIONS,
    TERMINAL_STATUSES,
    CommMarker,
    CommState,
    CommTarget,
    CommUpdate,
    GoalStatus,
    ServerEvent,
    ServerTransition,
    SimpleCallback,
    SimpleGoalState,
    SimpleUpdate,
    apply_comm_cancel,
    apply_comm_result,
    apply_comm_status,
    comm_state_name,
    comm_target,
    render_tables,
    rospy_status_name,
    server_transition,
    simple_get_state,
    simple_transition,
)

__all__ = [
    "ActionClient",
    "ActionServer",
    "CANCELED_BY_STAMP_TEXT",
    "COMM_TRANSITIONS",
    "CancelOutcome",
    "CancelRequest",
    "ClientGoalHandle",
    "CommMarker",
    "CommState",
    "CommTarget",
    "CommUpdate",
    "EventOutcome",
    "GoalArrival",
    "GoalIdGenerator",
    "GoalIdStamp",
    "GoalIdStyle",
    "GoalOutcome",
    "GoalStatus",
    "GoalTracker",
    "INVALID_TRANSITION",
    "NO_TRANSITION",
    "Publication",
    "PublicationTopic",
    "SERVER_STATES",
    "SERVER_TRANSITIONS",
    "STATUS_LIST_TIMEOUT_NS",
    "ServerEvent",
    "ServerGoalHandle",
    "ServerGoals",
    "ServerTransition",
    "SimpleActionClient",
    "SimpleActionServer",
    "SimpleCallback",
    "SimpleGoalState",
    "SimpleUpdate",
    "StatusOutcome",
    "TERMINAL_STATUSES",
    "UNINITIALIZED_GOAL_ID_TEXT",
    "UNINITIALIZED_HANDLE_TEXT",
    "apply_comm_cancel",
    "apply_comm_result",
    "apply_comm_status",
    "apply_goal_event",
    "cancel_matches",
    "comm_state_name",
    "comm_target",
    "goal_timelines",
    "is_expired",
    "plot_goals",
    "publish_status",
    "receive_cancel",
    "receive_goal",
    "render_tables",
    "rospy_status_name",
    "server_transition",
    "simple_get_state",
    "simple_transition",
]
