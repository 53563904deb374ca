"""DRV.NVSAVE and factory defaults across restarts of the board (`enip-host --nv-file`), with
pycomm3 (UCMM): phase "save" writes AIN.CUTOFF (parameter 1) and the TCP/IP host name, then
DRV.NVSAVE (parameter 1002, a command: one byte); phase "reset" sends Identity Reset type 1
(factory defaults); every phase reads both back.

Reads {"host", "phase", "cutoff"} on stdin. Prints one JSON line of named results (status
and reply hex).
"""
import json
import struct
import sys

from pycomm3 import CIPDriver

import kollmorgen_akd_common as akd

IDENTITY, TCPIP, RESET, DRV_NVSAVE = 0x01, 0xF5, 0x05, 1002


def main():
    req = json.load(sys.stdin)
    r = {}
    with CIPDriver(req["host"]) as d:
        if req["phase"] == "save":
            r["set_cutoff"] = akd.raw(d, akd.SET, akd.PARAMETER, 1, 1,
                                      struct.pack("<I", req["cutoff"]))
            r["set_host_name"] = akd.raw(d, akd.SET, TCPIP, 1, 6,
                                         struct.pack("<H", 4) + b"akd1")
            r["nvsave"] = akd.raw(d, akd.SET, akd.PARAMETER, DRV_NVSAVE, 1, b"\x01")
        if req["phase"] == "reset":
            r["reset"] = akd.raw(d, RESET, IDENTITY, 1, None, b"\x01")
        else:
            r["cutoff"] = akd.raw(d, akd.GET, akd.PARAMETER, 1, 1)
            r["host_name"] = akd.raw(d, akd.GET, TCPIP, 1, 6)
    print(json.dumps(r))


if __name__ == "__main__":
    main()
