"""TCP/IP Interface object (class 0xF5) settings that survive a restart, with pycomm3: phase
"set" sets attribute 5 (static interface configuration), 6 (host name), 8 (multicast TTL),
9 (multicast configuration: 4 addresses from 239.192.3.0) and 13 (inactivity timeout) and reads the status and configuration back; phase "check" (after a restart of the
board with the same --nv-file, at the new address) reads them again.

Reads {"host", "phase", "ip", "mask", "gateway", "domain"} on stdin. Prints one JSON line.
"""
import ipaddress
import json
import struct
import sys

from pycomm3 import CIPDriver

import explicit_request

TCPIP, GET, SET = 0xF5, 0x0E, 0x10


def request(driver, service, attribute, data=b""):
    """One UCMM request to instance 1; returns (general status or None, reply bytes)."""
    return explicit_request.request(driver, service, TCPIP, 1, attribute, data)


def udint(ip):
    return struct.pack("<I", int(ipaddress.IPv4Address(ip)))


def string(s):
    b = s.encode()
    return struct.pack("<H", len(b)) + b + (b"\0" if len(b) % 2 else b"")


def interface(ip, mask, gateway, domain):
    return b"".join(udint(a) for a in (ip, mask, gateway, "0.0.0.0", "0.0.0.0")) + string(domain)


def read(driver):
    out = {}
    for a in (1, 2, 5, 6, 8, 9, 13):
        status, value = request(driver, GET, a)
        out[str(a)] = {"status": status, "value": value.hex()}
    return out


def main():
    req = json.load(sys.stdin)
    out = {}
    wanted = interface(req["ip"], req["mask"], req["gateway"], req["domain"])
    out["expected_5"] = wanted.hex()
    with CIPDriver(req["host"]) as driver:
        if req["phase"] == "set":
            bad = interface("127.0.0.1", req["mask"], "0.0.0.0", "")
            out["set_bad_5"] = request(driver, SET, 5, bad)[0]
            out["set_5"] = request(driver, SET, 5, wanted)[0]
            out["set_6"] = request(driver, SET, 6, string("press-4"))[0]
            out["set_8"] = request(driver, SET, 8, bytes([5]))[0]
            mcast = bytes([1, 0]) + struct.pack("<H", 4) + udint("239.192.3.0")
            out["set_9"] = request(driver, SET, 9, mcast)[0]
            out["set_13"] = request(driver, SET, 13, struct.pack("<H", 30))[0]
        out["read"] = read(driver)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
