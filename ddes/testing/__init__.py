"""Testing helpers shipped with ddes: hypothesis strategies for messages, protocol machines,
the schedule explorer, and :func:`strict_worlds` (worlds whose ``run()`` raises the first error
of user code).  See docs/testing.md.

* :mod:`ddes.testing.actions`: any action server against the actionlib protocol;
* :mod:`ddes.testing.services`: a service handler under concurrent calls, errors, timeouts;
* :mod:`ddes.testing.rostime`: rates, timers and your node under a jumping ``/clock``;
* :mod:`ddes.testing.explore`: any scenario under perturbed latencies and tie orders.

The services, ROS-time and explorer names load their module on first use (the explorer's
``explore`` and ``replay`` functions are imported from :mod:`ddes.testing.explore`: the
package attribute ``explore`` is that module).
"""

from __future__ import annotations

import importlib
from typing import Any

from ddes.graph.failures import strict_worlds
from ddes.testing.actions import (
    ActionProtocolMachine,
    ProtocolViolation,
    replay_action_schedule,
    run_protocol_machine,
)
from ddes.testing.strategies import durations, field_values, messages, times

_LAZY = {
    "ServiceProtocolMachine": "services", "ServiceViolation": "services",
    "replay_service_schedule": "services", "run_service_machine": "services",
    "TimeProtocolMachine": "rostime", "TimeViolation": "rostime",
    "replay_time_schedule": "rostime", "run_time_machine": "rostime",
    "ExplorationFailure": "explore", "Perturbation": "explore", "run_perturbed": "explore",
}

__all__ = ["ActionProtocolMachine", "ExplorationFailure", "Perturbation", "ProtocolViolation",
           "ServiceProtocolMachine", "ServiceViolation", "TimeProtocolMachine", "TimeViolation",
           "durations", "field_values", "messages",
           "replay_action_schedule", "replay_service_schedule", "replay_time_schedule",
           "run_perturbed", "run_protocol_machine", "run_service_machine", "run_time_machine",
           "strict_worlds", "times"]


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'ddes.testing' has no attribute {name!r}")
    return getattr(importlib.import_module(f"ddes.testing.{module}"), name)
