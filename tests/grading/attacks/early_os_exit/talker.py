"""A1 early exit: os._exit(0) at import, skipping every cleanup."""
import os

os._exit(0)
