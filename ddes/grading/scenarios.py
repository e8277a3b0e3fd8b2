"""Which scenarios a grade runs: public ones from the seed, hidden ones from a keyed hash.

``scenario_seed(secret, exercise, student, attempt, index)`` is
``HMAC-SHA256(secret, "exercise/student/attempt/index")`` read as a 63-bit integer: the seed of
the ``index``-th hidden scenario of one student's attempt.  Without the course secret nobody can
compute it, so knowing the open-source checks does not tell which worlds a grade will use; with
it the instructor reproduces any of them.  The seeds change with every attempt (against tuning
to the feedback) and differ between students.

:func:`select_scenarios` turns an exercise's ``scenarios(seed, public)`` into the runs of one
grade, in the exercise's order: the public scenarios of ``seed``; unless ``public``, the hidden
ones too — without a :class:`HiddenKey` those of ``scenarios(seed, False)`` (an open default,
fine for practice and CI), with a key the ``i``-th hidden scenario is the ``i``-th hidden one of
``scenarios(scenario_seed(..., i), False)``, so an exercise needs nothing special to be graded
with secret scenarios (only: the number of hidden scenarios must not depend on the seed).
"""

from __future__ import annotations

import hashlib
import hmac
import os
from dataclasses import dataclass
from pathlib import Path

from ddes.errors import GradingError
from ddes.grading.exercise import Exercise, Scenario

__all__ = ["SECRET_ENV", "HiddenKey", "read_secret", "scenario_seed", "select_scenarios"]

#: The environment variable ``ddes grade`` reads the course secret from (``--secret-file`` wins).
SECRET_ENV = "DDES_GRADE_SECRET"


def scenario_seed(secret: bytes | str, exercise: str, student: str, attempt: int,
                  index: int) -> int:
    """The seed of hidden scenario ``index`` of ``student``'s ``attempt`` at ``exercise``:
    ``HMAC-SHA256(secret, f"{exercise}/{student}/{attempt}/{index}")``, its first 8 bytes
    big-endian, shifted right by one (0 <= seed < 2**63)."""
    key = secret.encode("utf-8") if isinstance(secret, str) else bytes(secret)
    if not key:
        raise GradingError("the course secret is empty: give a secret of at least 16 bytes "
                           f"(--secret-file FILE or ${SECRET_ENV})")
    for what, value in (("exercise", exercise), ("student", student)):
        if not isinstance(value, str) or "/" in value:
            raise GradingError(f"{what} {value!r} must be a string without '/' (it is a field "
                               "of the keyed hash)")
    if isinstance(attempt, bool) or not isinstance(attempt, int) or attempt < 0:
        raise GradingError(f"attempt {attempt!r} must be an integer >= 0")
    if isinstance(index, bool) or not isinstance(index, int) or index < 0:
        raise GradingError(f"index {index!r} must be an integer >= 0")
    # surrogateescape: a student id from a file name that is not UTF-8 hashes as its bytes
    mac = hmac.new(key, f"{exercise}/{student}/{attempt}/{index}".encode("utf-8",
                                                                         "surrogateescape"),
                   hashlib.sha256)
    return int.from_bytes(mac.digest()[:8], "big") >> 1


@dataclass(frozen=True)
class HiddenKey:
    """What hidden scenarios are derived from: the course secret, the student and the attempt."""

    secret: bytes
    student: str
    attempt: int = 0

    def __repr__(self) -> str:  # never print the secret
        return f"HiddenKey(secret=<{len(self.secret)} bytes>, student={self.student!r}, " \
               f"attempt={self.attempt})"


def read_secret(secret_file: str | None) -> bytes | None:
    """The course secret: the file's bytes (surrounding whitespace dropped), else
    ``$DDES_GRADE_SECRET``, else None."""
    if secret_file:
        path = Path(secret_file)
        if not path.is_file():
            raise GradingError(f"--secret-file {secret_file}: no such file")
        secret = path.read_bytes().strip()
        if not secret:
            raise GradingError(f"--secret-file {secret_file} is empty")
        return secret
    env = os.environ.get(SECRET_ENV, "").strip()
    return env.encode("utf-8") if env else None


def select_scenarios(exercise: Exercise, seed: int, public: bool,
                     key: HiddenKey | None = None) -> list[Scenario]:
    """The scenarios of one grade, in the exercise's order (see the module text)."""
    everything = exercise.scenarios(seed, public)
    if public:
        return [s for s in everything if not s.hidden]
    if key is None:
        return list(everything)
    count = sum(1 for s in everything if s.hidden)
    chosen, index = [], 0
    for s in everything:
        if not s.hidden:
            chosen.append(s)
            continue
        hidden = [h for h in exercise.scenarios(
            scenario_seed(key.secret, exercise.id, key.student, key.attempt, index), False)
            if h.hidden]
        if len(hidden) != count:
            raise GradingError(f"exercise {exercise.id}: scenarios() gave {len(hidden)} hidden "
                               f"scenario(s) for one seed and {count} for another; the number "
                               "must not depend on the seed")
        chosen.append(hidden[index])
        index += 1
    names = [s.name for s in chosen]
    if len(set(names)) != len(names):
        raise GradingError(f"exercise {exercise.id}: scenario names repeat: {names}")
    return chosen
