"""The course's exercises (after ETH Zurich, Programming for Robotics, exercises 1-3), registered
in :data:`ddes.grading.exercise.REGISTRY` on import.  Reference solutions and starters live in
``solutions/<id>/`` and ``exercises/<id>/`` of the repository."""

from ddes.grading.exercise import REGISTRY
from ddes.grading.exercises.ex1_console import EX1
from ddes.grading.exercises.ex2_package import EX2
from ddes.grading.exercises.ex3_pillar import EX3
from ddes.grading.exercises.ex4a_services import EX4A
from ddes.grading.exercises.ex4b_actions import EX4B
from ddes.grading.exercises.ex4c_time import EX4C
from ddes.grading.exercises.ex4d_bags import EX4D
from ddes.grading.exercises.ex5_safety import EX5

for _ex in (EX1, EX2, EX3, EX4A, EX4B, EX4C, EX4D, EX5):
    REGISTRY.register(_ex)

__all__ = ["EX1", "EX2", "EX3", "EX4A", "EX4B", "EX4C", "EX4D", "EX5"]
