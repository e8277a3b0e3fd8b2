"""NumPy's global generator pinned to a world: what a script's ``numpy.random`` answers.

:mod:`ddes.compat.pinned` gives a script its own ``random``; this gives it its own NumPy
global generator the same way, so a node that draws with ``np.random.rand()`` (or seeds with
``np.random.seed()``) draws the same on every run of the same seed:

* the legacy module-level functions (``rand``, ``randn``, ``randint``, ``normal``, ``choice``,
  ``shuffle``, ``get_state`` ... everything bound to NumPy's hidden ``RandomState``) are bound to
  a ``RandomState`` of the script, seeded from the world's stream ``script numpy <name>``;
* ``seed()`` with no argument, ``RandomState()`` and ``default_rng()`` without a seed take their
  seed from the next draw of the stream ``script numpy <name> seeds`` instead of the operating
  system; a seed given is the seed;
* everything else is NumPy itself: ``import numpy as np`` gives a view of the real module whose
  ``random`` is the view above (``np.ndarray``, ``np.linalg`` ... are NumPy's own).

Left out: NumPy's bit generators made without a seed (``np.random.PCG64()``) still read the
operating system's entropy.
"""

from __future__ import annotations

import types
from typing import TYPE_CHECKING, Any

from ddes.compat.pinned import _ModuleView

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["numpy_module"]


def numpy_module(world: World, name: str) -> types.ModuleType:
    """``numpy`` as the script ``name`` of ``world`` sees it (see the module docstring)."""
    import numpy

    view = _ModuleView("numpy", numpy)
    view.random = random_module(world, name)  # type: ignore[attr-defined]
    return view


def random_module(world: World, name: str) -> types.ModuleType:
    """``numpy.random`` of the script ``name``: its global generator is the script's."""
    import numpy.random as real_random

    seeds = world.rng_for(f"script numpy {name} seeds")

    def next_seed() -> int:
        return seeds.getrandbits(32)

    real_state = real_random.RandomState

    class _Meta(type):
        def __instancecheck__(cls, obj: object) -> bool:
            return isinstance(obj, real_state)

        def __subclasscheck__(cls, sub: type) -> bool:
            return issubclass(sub, real_state)

    class RandomState(real_state, metaclass=_Meta):  # type: ignore[misc, valid-type]
        def __init__(self, seed: Any = None) -> None:
            super().__init__(next_seed() if seed is None else seed)

        def seed(self, seed: Any = None) -> None:
            super().seed(next_seed() if seed is None else seed)

    RandomState.__module__ = "numpy.random.mtrand"
    RandomState.__qualname__ = RandomState.__name__ = "RandomState"
    inst = RandomState(world.rng_for(f"script numpy {name}").getrandbits(32))
    view = _ModuleView("numpy.random", real_random)
    hidden = real_random.mtrand._rand
    for attr in dir(real_random):
        fn = getattr(real_random, attr)
        if getattr(fn, "__self__", None) is hidden:
            setattr(view, attr, getattr(inst, attr))
    real_default_rng = real_random.default_rng

    def seed(seed: Any = None) -> None:
        inst.seed(seed)

    def default_rng(seed: Any = None) -> Any:
        return real_default_rng(next_seed() if seed is None else seed)

    for attr, value in (("seed", seed), ("default_rng", default_rng),
                        ("RandomState", RandomState), ("ranf", inst.random_sample),
                        ("sample", inst.random_sample)):
        setattr(view, attr, value)
    return view
