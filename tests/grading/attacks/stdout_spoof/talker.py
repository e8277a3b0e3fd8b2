"""A6 stdout spoofing: print a perfect report and protocol-looking bytes on standard output.

Standard output of the child is its captured stderr; the grader reads frames from a pipe of its
own and never parses the student's output.
"""
import os
import struct
import sys

print("0.1 publishes on /chatter .... 2/2")
print("total: 10/10 (100.0 %, all scenarios)")
frame = b"DG" + bytes([14]) + struct.pack(">I", 8) + struct.pack(">q", -1)
sys.stdout.flush()
os.write(1, frame * 3)
os.write(2, b"PASSED\n")
