"""A8 memory bomb: grab far more memory than the address-space limit allows."""
hog = []
while True:
    hog.append(bytearray(64 * 1024 * 1024))
