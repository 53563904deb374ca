"""QoS object (class 0x48) with pycomm3, then Class 1 I/O with the PyPI `ethernetip` package
(scheduled priority, its default) and a unicast ListIdentity over UDP 44818, so that the
capture holds every kind of packet the QoS object marks.

Phase "set" reads attributes 1-8, sets a DSCP out of range (64, expects 0x09) and then the
scheduled (5) and explicit (8) DSCP to the values given, and reads 1-8 again; phase "check"
(after a restart of the board with the same --nv-file) reads 1-8. Both phases then run an
exclusive-owner connection (generic profile: input 100, output 150, config 151) at a 10 ms
RPI for `seconds`, and send one ListIdentity datagram to UDP 44818.

Reads {"host", "phase", "scheduled", "explicit", "seconds"} on stdin. Prints one JSON line.
"""
import json
import socket
import struct
import sys
import time

from pycomm3 import CIPDriver

import explicit_request
from generic_owner import CONFIG, INPUT, OUTPUT, start

QOS, GET, SET = 0x48, 0x0E, 0x10


def read(driver):
    out = {}
    for a in range(1, 9):
        status, value = explicit_request.request(driver, GET, QOS, 1, a)
        out[str(a)] = value[0] if status == 0 and len(value) == 1 else {"status": status}
    return out


def class1(host, seconds):
    enip, conn, _inp, _out = start(host)
    try:
        opened = conn.sendFwdOpenReq(INPUT, OUTPUT, CONFIG, torpi=10, otrpi=10, multiplier=1)
        if opened == 0:
            conn.produce()
            time.sleep(seconds)
            conn.stopProduce()
            time.sleep(0.05)
            conn.sendFwdCloseReq(INPUT, OUTPUT, CONFIG)
        return opened
    finally:
        enip.stopIO()


def list_identity(host):
    """One ListIdentity (command 0x63) to UDP 44818; the reply's length, or None."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.settimeout(2.0)
        s.sendto(struct.pack("<HHII8sI", 0x63, 0, 0, 0, b"qos-test", 0), (host, 44818))
        try:
            return len(s.recv(1024))
        except socket.timeout:
            return None


def main():
    req = json.load(sys.stdin)
    host = req["host"]
    out = {}
    with CIPDriver(host) as driver:
        out["before"] = read(driver)
        if req["phase"] == "set":
            out["set_64"] = explicit_request.request(driver, SET, QOS, 1, 5, bytes([64]))[0]
            out["set_5"] = explicit_request.request(
                driver, SET, QOS, 1, 5, bytes([req["scheduled"]]))[0]
            out["set_8"] = explicit_request.request(
                driver, SET, QOS, 1, 8, bytes([req["explicit"]]))[0]
            out["after"] = read(driver)
    out["forward_open"] = class1(host, float(req["seconds"]))
    out["list_identity"] = list_identity(host)
    print(json.dumps(out))


main()
