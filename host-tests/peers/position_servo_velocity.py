"""Manual example 8.3 then 8.1 on the PositionServo profile: six configuration writes with
pycomm3 explicit messages, then velocity control over Class 1 with the PyPI `ethernetip`
package (input 105, output 106, configuration 103) and STATUS2 watched through an
input-only connection on 104 (heartbeat point 198).

Reads {"host", "rpi_ms", "multiplier", "reference"} on stdin. Prints one JSON line: the
write statuses and read-back values, the Forward_Open statuses, and the ramp figures (times
in ms since the output data changed, slopes in units/s²).
"""
import json
import sys
import time

from pycomm3 import CIPDriver
from ethernetip.ethernetip import EtherNetIP

import position_servo_common as ps

# Example 8.3's list: drive mode velocity, internal reference, enable switch inhibit only,
# accel/decel limits on, accel 1000, decel 1000 (sent as REALs like the example's list).
CONFIG_LIST = [(34, 1.0), (37, 1.0), (29, 0.0), (75, 1.0), (76, 1000.0), (77, 1000.0)]


def after(samples, t0, decode):
    return [(t, decode(d)) for t, d in samples if t >= t0]


def ramp(points, target):
    """First motion, first time at target, and the slope between 10 % and 90 %."""
    moving = [t for t, v in points if abs(v) > 0]
    reached = [t for t, v in points if v == target]
    middle = [(t, v) for t, v in points if 0.1 * abs(target) < abs(v) < 0.9 * abs(target)]
    return {"first_motion_ms": moving[0] if moving else None,
            "reached_ms": reached[0] if reached else None,
            "slope": ps.slope(middle), "points": len(middle)}


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult, ref = req["host"], req["rpi_ms"], req["multiplier"], float(req["reference"])
    out = {}
    with CIPDriver(ip) as driver:
        out["writes"] = [ps.set_real(driver, var, value) for var, value in CONFIG_LIST]
        out["readback"] = [ps.get_int(driver, var) for var, _ in CONFIG_LIST]
        enip = EtherNetIP(ip)
        enip.startIO()
        t0 = time.monotonic()
        status = ps.Class1(enip, ip, ps.STATUS_IO, 8, ps.INPUT_ONLY, 0, rpi, mult, t0)
        owner = ps.Class1(enip, ip, ps.MONITOR, 36, ps.BASIC, 8, rpi, mult, t0)
        try:
            owner.write(ps.control(0.0, 0.0))
            out["forward_open"] = [status.open(), owner.open()]
            time.sleep(0.3)
            enabled_bit = lambda d: ps.words(d, "I")[0] & 1
            out["status2_before"] = ps.words(status.read(), "I")[0]
            t_enable = (time.monotonic() - t0) * 1000.0
            owner.write(ps.control(1.0, ref))
            time.sleep(0.2 + abs(ref) / 1000.0)
            t_stop = (time.monotonic() - t0) * 1000.0
            owner.write(ps.control(1.0, 0.0))
            time.sleep(0.2 + abs(ref) / 1000.0)
            t_disable = (time.monotonic() - t0) * 1000.0
            owner.write(ps.control(0.0, 0.0))
            time.sleep(0.2)
            velocity = lambda d: ps.words(d, "f")[0]
            up = [(t - t_enable, v) for t, v in after(owner.samples, t_enable, velocity) if t < t_stop]
            down = [(t - t_stop, v) for t, v in after(owner.samples, t_stop, velocity) if t < t_disable]
            bits = after(status.samples, t_enable, enabled_bit)
            on = [t for t, b in bits if b and t < t_disable]
            off = [t for t, b in bits if not b and t >= t_disable]
            out["up"] = ramp(up, ref)
            out["down"] = ramp([(t, ref - v) for t, v in down], ref)
            out["velocity_at_stop"] = down[-1][1] if down else None
            out["enabled_after_ms"] = on[0] - t_enable if on else None
            out["disabled_after_ms"] = off[0] - t_disable if off else None
            out["status2_after"] = ps.words(status.read(), "I")[0]
            out["samples"] = len(owner.samples)
        finally:
            out["forward_close"] = [owner.close(), status.close()]
            enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
