"""tf_conversions (Noetic) for a rospy script: ``import tf_conversions``.

Noetic's package is ``posemath`` (PyKDL frames from and to messages, ``tf_conversions.posemath``,
re-exported by the package) and ``transformations``, a copy of tf.transformations
(``tf_conversions.transformations``).  ddes provides ``transformations``
(:mod:`ddes.compat.tf_conversions.transformations`, the same module as ``tf.transformations``)
and, deliberately, no ``posemath``: it needs PyKDL, which ddes does not have.  ``import
tf_conversions.posemath``, ``tf_conversions.fromMsg`` and the other posemath names therefore raise
ImportError / AttributeError.
"""

from __future__ import annotations

from typing import Any

from ddes.compat.tf_conversions import transformations

__all__ = ["transformations"]


def __getattr__(name: str) -> Any:
    raise AttributeError(
        f"module 'tf_conversions' has no attribute '{name}' (ddes provides "
        "tf_conversions.transformations only: posemath needs PyKDL, which ddes does not have)")
