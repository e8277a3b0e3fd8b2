"""tf's Python API (Noetic's ``tf`` package) for a rospy script: ``import tf``.

As in Noetic, tf1 is a layer over tf2: ``tf.TransformListener()``, ``tf.Transformer``,
``tf.TransformerROS`` (:mod:`ddes.compat.tf.listener`) hold a tf2_ros Buffer
(:mod:`ddes.compat.tf2_ros`, waits blocking the script's node on simulated time), and
``tf.TransformBroadcaster()`` (:mod:`ddes.compat.tf.broadcaster`) is tf2_ros's broadcaster with
tf1's ``sendTransform(translation, rotation, time, child, parent)``.  ``tf.transformations``
(:mod:`ddes.compat.tf.transformations`) is imported with the package, as Noetic's
``tf/__init__.py`` does through its listener.

The exceptions are tf2's, as in Noetic: ``tf.Exception`` *is* ``tf2_ros.TransformException``,
and ``tf.LookupException``, ``tf.ConnectivityException`` and ``tf.ExtrapolationException`` are
tf2_ros's classes, so ``except tf2_ros.LookupException`` catches what tf raises and
``except tf.Exception`` catches every tf2 error.  Deviations: those of the submodules (see their
docstrings); ``tf.msg``/``tf.srv`` are the world's message packages (``tf/tfMessage``).
"""

from __future__ import annotations

from ddes.compat.tf import broadcaster, listener, transformations
from ddes.compat.tf.broadcaster import TransformBroadcaster
from ddes.compat.tf.listener import Transformer, TransformerROS, TransformListener
from ddes.compat.tf2_ros import ConnectivityException, ExtrapolationException, LookupException
from ddes.compat.tf2_ros import TransformException as Exception  # noqa: A004 - tf's own name

__all__ = ["ConnectivityException", "Exception", "ExtrapolationException", "LookupException",
           "TransformBroadcaster", "TransformListener", "Transformer", "TransformerROS",
           "broadcaster", "listener", "transformations"]
