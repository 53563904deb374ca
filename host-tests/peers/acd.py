"""Address Conflict Detection as the TCP/IP Interface object (class 0xF5) reports it, with
pycomm3: reads attributes 1 (status), 2 (capability), 10 (SelectAcd) and 11
(LastConflictDetected).

Reads {"host"} on stdin. Prints one JSON line: {"<attribute>": {"status", "value" (hex)}}.
"""
import json
import sys

from pycomm3 import CIPDriver

import explicit_request

TCPIP, GET = 0xF5, 0x0E


def main():
    req = json.load(sys.stdin)
    out = {}
    with CIPDriver(req["host"]) as driver:
        for a in (1, 2, 10, 11):
            status, value = explicit_request.request(driver, GET, TCPIP, 1, a)
            out[str(a)] = {"status": status, "value": value.hex()}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
