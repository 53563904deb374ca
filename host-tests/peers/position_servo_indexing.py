"""Manual example 8.2 on the PositionServo profile: position mode configured with pycomm3,
the drive enabled and monitored over Class 1 with the PyPI `ethernetip` package (output 106,
input 105; STATUS2 through an input-only connection on 104), then a relative move started by
writing 10 to variable 93 (MOVED) with an explicit message, as the example's indexer does.

Reads {"host", "rpi_ms", "multiplier", "distance"} on stdin. Prints one JSON line: statuses,
the actual position (105 word 1) before and after, the explicit read of variable 215 after,
and when STATUS2 bit 9 (motion completed) cleared and set again (ms after the write).
"""
import json
import sys
import time

from pycomm3 import CIPDriver
from ethernetip.ethernetip import EtherNetIP

import position_servo_common as ps

# Table 27: position mode, internal reference, enable switch inhibit only.
SETUP = [(34, 2), (37, 1), (29, 0)]
MOTION_COMPLETED = 1 << 9


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult, distance = req["host"], req["rpi_ms"], req["multiplier"], req["distance"]
    out = {}
    with CIPDriver(ip) as driver:
        out["writes"] = [ps.set_int(driver, var, value) for var, value in SETUP]
        enip = EtherNetIP(ip)
        enip.startIO()
        t0 = time.monotonic()
        status = ps.Class1(enip, ip, ps.STATUS_IO, 8, ps.INPUT_ONLY, 0, rpi, mult, t0)
        owner = ps.Class1(enip, ip, ps.MONITOR, 36, ps.BASIC, 8, rpi, mult, t0)
        try:
            owner.write(ps.control(1.0, 0.0))
            out["forward_open"] = [status.open(), owner.open()]
            status2 = lambda d: ps.words(d, "I")[0]
            out["enabled"] = status.wait_for(lambda d: status2(d) & 1, 2.0) is not None
            time.sleep(0.1)
            out["position_before"] = ps.words(owner.read(), "f")[1]
            t_move = (time.monotonic() - t0) * 1000.0
            out["moved"] = ps.set_real(driver, 93, distance)
            done = lambda d: status2(d) & MOTION_COMPLETED
            cleared = status.wait_for(lambda d: not done(d), 1.0)
            completed = status.wait_for(done, 10.0)
            # Let the receiving thread of 105 catch up (it may lag under load).
            time.sleep(0.05 + 4 * rpi / 1000.0)
            out["cleared_ms"] = cleared - t_move if cleared is not None else None
            out["completed_ms"] = completed - t_move if completed is not None else None
            out["position_after"] = ps.words(owner.read(), "f")[1]
            out["variable_215"] = ps.get_real(driver, 215)
            out["status2_after"] = status2(status.read())
        finally:
            out["forward_close"] = [owner.close(), status.close()]
            enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
