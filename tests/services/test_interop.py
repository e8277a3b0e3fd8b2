"""ddes's handler-return rules against real rospy's ``convert_return_to_response``.

The same handler return values are converted by rospy (genpy classes, system
Python) and by ddes.  Successes must give the same fields; failures the same
exception type and a text that starts with rospy's (ddes's generated
constructors append a hint after a ``;``).
"""

from __future__ import annotations

import json
from typing import Any

import pytest

from ddes.errors import ServiceException
from ddes.msg import get_service_class, message_to_dict
from ddes.services.convert import args_kwds_to_request, convert_return_to_response

RETURNS = [
    "True", "False", "None", "5", "'x'", "[]", "()", "{}", "[True]", "(True, 'ok')",
    "[False, 'no']", "(1, 2, 3)", "{'success': True}", "{'message': 'hi', 'success': False}",
    "{'bad': 1}", "{1, 2}", "{'success': True, 'oops': 2}",
]
SERVICES = ["std_srvs/SetBool", "std_srvs/Empty", "std_srvs/Trigger"]

ROS_SCRIPT = r"""
import json, importlib
from rospy.impl.tcpros_service import convert_return_to_response
from rospy.service import ServiceException
import rospy.msg
out = {}
for srv in %(services)r:
    pkg, name = srv.split('/')
    cls = getattr(importlib.import_module(pkg + '.srv'), name)
    for text in %(returns)r:
        try:
            resp = convert_return_to_response(eval(text), cls._response_class)
            out[srv + ' ' + text] = ['ok', {s: getattr(resp, s) for s in resp.__slots__}]
        except ServiceException as e:
            out[srv + ' ' + text] = ['ServiceException', str(e)]
from std_srvs.srv import SetBoolRequest, TriggerRequest, EmptyRequest
for label, args in [('trigger-for-setbool', (TriggerRequest(),)), ('empty-for-trigger', (SetBoolRequest(),))]:
    data_class = SetBoolRequest if label.startswith('trigger') else TriggerRequest
    try:
        rospy.msg.args_kwds_to_message(data_class, args, {})
        out[label] = ['ok', None]
    except TypeError as e:
        out[label] = ['TypeError', str(e)]
try:
    rospy.msg.args_kwds_to_message(SetBoolRequest, (True,), {'data': True})
except TypeError as e:
    out['both'] = ['TypeError', str(e)]
print(json.dumps(out))
"""


def _ddes_results() -> dict[str, Any]:
    out: dict[str, Any] = {}
    for srv in SERVICES:
        cls = get_service_class(srv)
        for text in RETURNS:
            try:
                resp = convert_return_to_response(eval(text), cls._response_class)  # noqa: S307
                out[f"{srv} {text}"] = ["ok", message_to_dict(resp)]
            except ServiceException as exc:
                out[f"{srv} {text}"] = ["ServiceException", str(exc)]
    set_bool = get_service_class("std_srvs/SetBool")
    trigger = get_service_class("std_srvs/Trigger")
    for label, data_class, args in (
            ("trigger-for-setbool", set_bool._request_class, (trigger._request_class(),)),
            ("empty-for-trigger", trigger._request_class, (set_bool._request_class(),))):
        try:
            args_kwds_to_request(data_class, args, {})
            out[label] = ["ok", None]
        except TypeError as exc:
            out[label] = ["TypeError", str(exc)]
    try:
        args_kwds_to_request(set_bool._request_class, (True,), {"data": True})
    except TypeError as exc:
        out["both"] = ["TypeError", str(exc)]
    return out


@pytest.mark.ros
def test_convert_return_to_response_matches_rospy(ros_python: Any) -> None:
    ros = ros_python(ROS_SCRIPT % {"services": SERVICES, "returns": RETURNS}, as_json=True)
    ours = json.loads(json.dumps(_ddes_results()))
    assert sorted(ros) == sorted(ours)
    for key, (kind, value) in ros.items():
        our_kind, our_value = ours[key]
        assert our_kind == kind, key
        if kind == "ok":
            assert our_value == value, key
        else:
            assert our_value.startswith(value), (key, our_value, value)
            rest = our_value[len(value):]
            assert rest == "" or rest.startswith("; "), (key, rest)
