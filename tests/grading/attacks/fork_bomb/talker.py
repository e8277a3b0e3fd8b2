"""A8 fork bomb: fork until something gives (the audit hook refuses fork; RLIMIT_NPROC and the
process-group kill stand behind it)."""
import os

while True:
    try:
        os.fork()
    except OSError:
        pass
