"""Exclusive owner for position_servo_ownership.py: opens a Class 1 connection with the PyPI
`ethernetip` package (output 106 enabling the drive at a velocity reference, input 105),
prints one JSON line once it produces, then produces until it is killed.

Arguments: host rpi_ms multiplier reference (and at most `seconds`, after which it exits).
"""
import json
import sys
import time

from ethernetip.ethernetip import EtherNetIP

import position_servo_common as ps


def main():
    ip, rpi, mult, ref, seconds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), \
        float(sys.argv[4]), float(sys.argv[5])
    enip = EtherNetIP(ip)
    enip.startIO()
    owner = ps.Class1(enip, ip, ps.MONITOR, 36, ps.BASIC, 8, rpi, mult, time.monotonic())
    owner.write(ps.control(1.0, ref))
    print(json.dumps({"forward_open": owner.open()}), flush=True)
    time.sleep(seconds)  # killed long before, normally


if __name__ == "__main__":
    main()
