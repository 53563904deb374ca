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

import ethernetip.ethernetip as enip_mod
from ethernetip.ethernetip import EtherNetIP

# Its producer never runs faster than this many ms otherwise.
enip_mod.config.UDP_IO_MIN_RPI = 0

req = json.load(sys.stdin)
ip, rpi, seconds = req["host"], int(req["rpi_ms"]), float(req["seconds"])
multicast = bool(req.get("multicast", False))
result = {"forward_open": None, "echoed": False, "forward_close": None, "reopen": None}


def bits_to_bytes(bits):
    return bytes(sum(1 << b for b in range(8) if bits[i * 8 + b]) for i in range(len(bits) // 8))


enip = EtherNetIP(ip)
conn = enip.explicit_conn(ip)
conn.registerSession()
inp = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_INPUT, 32, 100, conn)
out = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_OUTPUT, 32, 150, conn)
enip.startIO()
try:
    result["forward_open"] = conn.sendFwdOpenReq(100, 150, 151, torpi=rpi, otrpi=rpi,
                                                 multiplier=1, multicast=multicast)
    if result["forward_open"] == 0:
        pattern = bytes((i * 7 + 3) & 0xFF for i in range(32))
        for i, byte in enumerate(pattern):
            for b in range(8):
                out[i * 8 + b] = bool(byte & (1 << b))
        conn.produce()
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:  # bounded by time
            if bits_to_bytes(inp) == pattern:
                result["echoed"] = True
            time.sleep(0.01)
        conn.stopProduce()
        time.sleep(0.05)
        result["forward_close"] = conn.sendFwdCloseReq(100, 150, 151)
        result["reopen"] = conn.sendFwdOpenReq(100, 150, 151, torpi=rpi, otrpi=rpi, multiplier=1)
        if result["reopen"] == 0:
            conn.sendFwdCloseReq(100, 150, 151)
finally:
    enip.stopIO()
print(json.dumps(result))
