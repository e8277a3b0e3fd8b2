"""Drop-in modules for code written for ROS: ``from ddes.compat import rospy``.

:mod:`ddes.compat.rospy` offers rospy's module-level API on the node of the
running greenlet (:mod:`ddes.graph.blocking`), so a rospy script runs
unchanged on simulated time; :mod:`ddes.compat.scripts` runs such a script as
a node, with ``import rospy`` and the message modules (``from std_msgs.msg
import String``) resolving to ddes for that script's code only.  See
docs/rospy.md.
"""
