"""Probe: the parameters param_talker.launch and its node set, as JSON (a rospy script)."""

import json

import rospy

rospy.init_node("param_probe", anonymous=True)
print(json.dumps({name: rospy.get_param(name) for name in ("/foo", "/global_example")},
                 sort_keys=True))
