"""Manual 8.4 on the PositionServo profile: an exclusive owner (position_servo_owner.py, the
PyPI `ethernetip` package) enables the drive in velocity mode; pycomm3 sees EXSTATUS
(variable 83) bit 24 set, then the owner is killed (SIGKILL, no Forward_Close) and pycomm3
polls EXSTATUS until the bit clears, then reads STATUS (54): the drive must have disabled.

Reads {"host", "rpi_ms", "multiplier", "reference"} on stdin (multiplier: the Forward_Open
timeout multiplier code, the watchdog being RPI x 4 << code). Prints one JSON line.
"""
import json
import os
import select
import signal
import subprocess
import sys
import time

from pycomm3 import CIPDriver

import position_servo_common as ps

EXSTATUS, STATUS, OWNED, ENABLED = 83, 54, 1 << 24, 1


def poll(driver, predicate, seconds):
    """Polls EXSTATUS (bounded); returns (ms waited, last value, reads) once it holds."""
    start = time.monotonic()
    reads, value = 0, None
    while time.monotonic() - start < seconds:
        value = ps.get_int(driver, EXSTATUS)
        reads += 1
        if value is not None and predicate(value):
            return (time.monotonic() - start) * 1000.0, value, reads
    return None, value, reads


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult, ref = req["host"], req["rpi_ms"], req["multiplier"], req["reference"]
    out = {"watchdog_ms": rpi * (4 << mult)}
    here = os.path.dirname(os.path.abspath(__file__))
    with CIPDriver(ip) as driver:
        out["writes"] = [ps.set_int(driver, 34, 1), ps.set_int(driver, 37, 1)]
        child = subprocess.Popen(
            [sys.executable, os.path.join(here, "position_servo_owner.py"), ip, str(rpi),
             str(mult), str(ref), "30"], stdout=subprocess.PIPE)
        try:
            ready, _, _ = select.select([child.stdout], [], [], 20)
            out["owner"] = json.loads(child.stdout.readline()) if ready else None
            _, out["exstatus_owned"], _ = poll(driver, lambda v: v & OWNED, 5.0)
            time.sleep(0.3)
            out["status_owned"] = ps.get_int(driver, STATUS)
            child.send_signal(signal.SIGKILL)
            waited, out["exstatus_after"], out["reads"] = poll(driver, lambda v: not v & OWNED, 5.0)
            out["cleared_ms"] = waited
            out["status_after"] = ps.get_int(driver, STATUS)
        finally:
            child.kill()
            child.wait(timeout=10)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
