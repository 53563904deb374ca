"""One pycomm3 session that reads the Identity product name (class 1, instance 1,
attribute 7, unconnected) every `period_ms` for `seconds`, as an HMI polling a device would.

Reads {"host": str, "seconds": float, "period_ms": int} as JSON from stdin. Prints one JSON
line: {"reads": [[unix_time, latency_ms or null], ...], "error": str|null}: one entry per
read, latency null for a read that failed (after which the session is opened again).
"""
import json
import sys
import time

from pycomm3 import CIPDriver, Services

req = json.load(sys.stdin)
end = time.monotonic() + req["seconds"]
period = req["period_ms"] / 1000.0
reads = []
error = None
driver = None
nxt = time.monotonic()
while time.monotonic() < end:
    at = time.time()
    t = time.monotonic()
    try:
        if driver is None:
            driver = CIPDriver(req["host"])
            driver._cfg["socket_timeout"] = 2.0
            driver.open()
        r = driver.generic_message(service=Services.get_attribute_single, class_code=1,
                                   instance=1, attribute=7, connected=False,
                                   unconnected_send=False, route_path=False, name="name")
        if r.error:
            raise RuntimeError(r.error)
        reads.append([at, (time.monotonic() - t) * 1000.0])
    except Exception as e:  # a failed read is a figure, not the end of the run
        error = str(e)
        reads.append([at, None])
        try:
            if driver is not None:
                driver.close()
        except Exception:
            pass
        driver = None
    nxt += period
    time.sleep(max(0.0, nxt - time.monotonic()))
if driver is not None:
    driver.close()
print(json.dumps({"reads": reads, "error": error}))
