"""Manual table 13 on the PositionServo profile: input DataLink A (variable 261) set to
0xC00000BC with pycomm3 makes word 5 of assembly 105, read over Class 1 with the PyPI
`ethernetip` package, carry the phase current (variable 188) as a REAL.

Reads {"host", "rpi_ms", "multiplier", "reference"} on stdin; runs the drive in velocity mode
at `reference` units/s so the phase current is steady. Prints one JSON line: statuses, 105
words 3 (phase current) and 5 (link A) before and after, and the explicit reads of 261 and
188.
"""
import json
import sys
import time

from pycomm3 import CIPDriver
from ethernetip.ethernetip import EtherNetIP

import position_servo_common as ps

SETUP = [(34, 1), (37, 1), (75, 1)]
LINK_A_IN, PHASE_CURRENT, CONTROL = 261, 188, 0xC00000BC


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult, ref = req["host"], req["rpi_ms"], req["multiplier"], float(req["reference"])
    out = {}
    with CIPDriver(ip) as driver:
        out["writes"] = [ps.set_int(driver, var, value) for var, value in SETUP]
        enip = EtherNetIP(ip)
        enip.startIO()
        t0 = time.monotonic()
        owner = ps.Class1(enip, ip, ps.MONITOR, 36, ps.BASIC, 8, rpi, mult, t0)
        try:
            owner.write(ps.control(1.0, ref))
            out["forward_open"] = owner.open()
            out["at_speed"] = owner.wait_for(lambda d: ps.words(d, "f")[0] == ref, 5.0) is not None
            time.sleep(0.05)
            monitor = ps.words(owner.read(), "f")
            out["before"] = {"word3": monitor[3], "word5": monitor[5]}
            out["link_write"] = ps.set_int(driver, LINK_A_IN, CONTROL)
            out["link_readback"] = ps.get_int(driver, LINK_A_IN)
            changed = owner.wait_for(lambda d: ps.words(d, "f")[5] != monitor[5], 2.0)
            time.sleep(2 * rpi / 1000.0)
            monitor = ps.words(owner.read(), "f")
            out["after"] = {"word3": monitor[3], "word5": monitor[5]}
            out["changed"] = changed is not None
            out["variable_188"] = ps.get_real(driver, PHASE_CURRENT)
        finally:
            out["forward_close"] = owner.close()
            enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
