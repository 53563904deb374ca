"""The LLDP Management (class 0x109) and LLDP Data Table (class 0x10A) objects, with pycomm3:
phase "setup" sets the TCP/IP host name (0xF5 attribute 6, the LLDP System Name), tries
out-of-range LLDP settings and a read-only attribute, sets LLDP Enable (attribute 1),
msgTxInterval (2) and msgTxHold (3), and reads 0x109 attributes 1-5 and the MAC address
(Ethernet Link attribute 3) back; phase "table" reads the Data Table's instance count and
each instance's attributes 1-9, and 0x109's Last Change.

Reads {"host", "host_name", "tx_interval", "tx_hold"} on stdin. Prints one JSON line.
"""
import json
import struct
import sys

from pycomm3 import CIPDriver

import explicit_request

TCPIP, LINK, MANAGEMENT, TABLE = 0xF5, 0xF6, 0x109, 0x10A
GET, SET = 0x0E, 0x10


def raw(driver, service, cls, instance, attribute, data=b""):
    return explicit_request.raw(driver, service, cls, instance, attribute, data)


def string(s):
    b = s.encode()
    return struct.pack("<H", len(b)) + b + (b"\0" if len(b) % 2 else b"")


def setup(driver, req):
    out = {"host_name": raw(driver, SET, TCPIP, 1, 6, string(req["host_name"]))}
    out["bad_interval"] = raw(driver, SET, MANAGEMENT, 1, 2, struct.pack("<H", 0))
    out["bad_hold"] = raw(driver, SET, MANAGEMENT, 1, 3, bytes([101]))
    out["bad_enable"] = raw(driver, SET, MANAGEMENT, 1, 1, struct.pack("<HB", 2, 0x04))
    out["datastore_set"] = raw(driver, SET, MANAGEMENT, 1, 4, struct.pack("<H", 0))
    out["enable"] = raw(driver, SET, MANAGEMENT, 1, 1, struct.pack("<HB", 2, 0x03))
    out["interval"] = raw(driver, SET, MANAGEMENT, 1, 2, struct.pack("<H", req["tx_interval"]))
    out["hold"] = raw(driver, SET, MANAGEMENT, 1, 3, bytes([req["tx_hold"]]))
    out["read"] = {str(a): raw(driver, GET, MANAGEMENT, 1, a) for a in range(1, 6)}
    out["mac"] = raw(driver, GET, LINK, 1, 3)
    return out


def table(driver):
    count = raw(driver, GET, TABLE, 0, 3)
    out = {"count": count, "instances": {}}
    n = struct.unpack("<H", bytes.fromhex(count["data"]))[0] if count["status"] == 0 else 0
    max_instance = raw(driver, GET, TABLE, 0, 2)
    top = struct.unpack("<H", bytes.fromhex(max_instance["data"]))[0] if n else 0
    for i in range(1, top + 1):
        out["instances"][str(i)] = {str(a): raw(driver, GET, TABLE, i, a) for a in range(1, 10)}
    out["last_change"] = raw(driver, GET, MANAGEMENT, 1, 5)
    return out


def main():
    req = json.load(sys.stdin)
    with CIPDriver(req["host"]) as driver:
        out = setup(driver, req) if req["phase"] == "setup" else table(driver)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
