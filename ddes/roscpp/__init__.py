"""roscpp on simulated time: C++ nodes as processes in lockstep with a world.

``host`` serves the external-node protocol (``protocol``, docs/external-nodes.md) on an
ordinary roscpp-style node of the world; ``gencpp`` writes message headers in gencpp's layout;
``catkin`` builds a workspace against ddes's own catkin configuration; ``cpp/`` holds the
C++ client library (docs/roscpp.md).
"""
