"""Class 1 exclusive owner with the PyPI `ethernetip` package on the generic profile
(input 100, output 150, config 151).

Reads one JSON document from stdin: {"host": str, "rpi_ms": int, "seconds": float,
"multicast": bool}. Writes a pattern in O->T, watches T->O for it, then Forward_Close, and
reopens once to show the slot was freed. Prints one JSON line:
{"forward_open", "echoed", "forward_close", "reopen"} (0 = success, else extended status).
"""
import json
import sys
import time

from generic_owner import CONFIG, INPUT, OUTPUT, put, start, to_bytes

req = json.load(sys.stdin)
ip, rpi, seconds = req["host"], int(req["rpi_ms"]), float(req["seconds"])
multicast = bool(req.get("multicast", False))
result = {"forward_open": None, "echoed": False, "forward_close": None, "reopen": None}

enip, conn, inp, out = start(ip)
try:
    result["forward_open"] = conn.sendFwdOpenReq(INPUT, OUTPUT, CONFIG, torpi=rpi, otrpi=rpi,
                                                 multiplier=1, multicast=multicast)
    if result["forward_open"] == 0:
        pattern = bytes((i * 7 + 3) & 0xFF for i in range(32))
        put(out, pattern)
        conn.produce()
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:  # bounded by time
            if to_bytes(inp) == pattern:
                result["echoed"] = True
            time.sleep(0.01)
        conn.stopProduce()
        time.sleep(0.05)
        result["forward_close"] = conn.sendFwdCloseReq(INPUT, OUTPUT, CONFIG)
        result["reopen"] = conn.sendFwdOpenReq(INPUT, OUTPUT, CONFIG, torpi=rpi, otrpi=rpi,
                                               multiplier=1)
        if result["reopen"] == 0:
            conn.sendFwdCloseReq(INPUT, OUTPUT, CONFIG)
finally:
    enip.stopIO()
print(json.dumps(result))
