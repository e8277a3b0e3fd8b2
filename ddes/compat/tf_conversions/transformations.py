"""tf_conversions.transformations: Noetic's copy of tf.transformations.

The very functions of :mod:`ddes.compat.tf.transformations` (see its docstring for what they
follow and their deviations), under this name.
"""

from __future__ import annotations

from ddes.compat.tf.transformations import *  # noqa: F403 - the same module's functions
from ddes.compat.tf.transformations import __all__ as __all__
from ddes.compat.tf.transformations import __getattr__ as __getattr__
