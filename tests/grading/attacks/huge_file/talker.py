"""A8 huge file: write without end into the working copy (RLIMIT_FSIZE ends it)."""
chunk = b"x" * (1 << 20)
with open("huge.bin", "wb") as f:
    while True:
        f.write(chunk)
