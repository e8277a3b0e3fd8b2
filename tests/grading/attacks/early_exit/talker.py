"""A1 early exit: sys.exit(0) before doing anything (an exit-code grader would pass it)."""
import sys

sys.exit(0)
