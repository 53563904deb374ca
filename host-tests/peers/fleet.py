"""A fleet of devices in one `enip-host --devices` process, seen from the network: pycomm3
reads each device's Identity object, then the PyPI `ethernetip` package opens a Class 1
exclusive owner on every device at once (one originator, one UDP 2222 socket), counts the
T->O datagrams of each while they all run, and closes them.

Reads one JSON document from stdin: {"rpi_ms": int, "seconds": float, "devices": [{"host",
"input", "in_size", "output", "out_size", "config"}]}. Prints one JSON line: {"devices":
[{"host", "identity": {key: text}, "forward_open", "received", "forward_close"}]} (statuses
0 on success, else the extended status; "received" the T->O datagrams of its connection).
"""
import collections
import json
import sys
import time

import ethernetip.ethernetip as enip_mod
from ethernetip.ethernetip import EtherNetIP
from pycomm3 import CIPDriver

from identity import read_identity

# Its producer never runs faster than this many ms otherwise.
enip_mod.config.UDP_IO_MIN_RPI = 0

# T->O datagrams per connection ID, counted as the package's receiver parses them.
RECEIVED = collections.Counter()


class CountedPacket(enip_mod.UdpRecvDataPacket):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        RECEIVED[self.conn_id] += 1


enip_mod.UdpRecvDataPacket = CountedPacket

req = json.load(sys.stdin)
rpi, seconds, devices = int(req["rpi_ms"]), float(req["seconds"]), req["devices"]
results = [{"host": d["host"], "identity": None, "forward_open": None, "received": 0,
            "forward_close": None} for d in devices]

for d, r in zip(devices, results):
    with CIPDriver(d["host"]) as driver:
        r["identity"] = {key: text for _, key, _, text in read_identity(driver)}

enip = EtherNetIP(devices[0]["host"])
owners = []
for d in devices:
    conn = enip.explicit_conn(d["host"])
    conn.registerSession()
    enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_INPUT, d["in_size"], d["input"], conn)
    enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_OUTPUT, d["out_size"], d["output"], conn)
    owners.append(conn)
enip.startIO()
try:
    for d, conn, r in zip(devices, owners, results):
        r["forward_open"] = conn.sendFwdOpenReq(d["input"], d["output"], d["config"], torpi=rpi,
                                                otrpi=rpi, multiplier=2, inputsz=d["in_size"],
                                                outputsz=d["out_size"])
        if r["forward_open"] == 0:
            conn.produce()
    time.sleep(seconds)  # every owner runs at once
    for d, conn, r in zip(devices, owners, results):
        if r["forward_open"] == 0:
            r["received"] = RECEIVED[conn.toconnid]
            conn.stopProduce()
    time.sleep(0.05)
    for d, conn, r in zip(devices, owners, results):
        if r["forward_open"] == 0:
            r["forward_close"] = conn.sendFwdCloseReq(d["input"], d["output"], d["config"])
finally:
    enip.stopIO()
print(json.dumps({"devices": results}))
