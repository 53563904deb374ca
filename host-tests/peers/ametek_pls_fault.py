"""The 7500 PLS with a resolver fault (board option --pls-resolver-fault on): pycomm3 reads
Identity status (bit 10, major recoverable fault) and tries a home offset, which the module
refuses (0x10, error code 3); the PyPI `ethernetip` package owns the I/O and reads input
words 9-10 (RPM 0, resolver fault 1) and 15-17 (3, 36, 1).

Reads {"host", "rpi_ms", "multiplier"} on stdin. Prints one JSON line.
"""
import json
import struct
import sys

from pycomm3 import CIPDriver

import ametek_pls_common as pls
import explicit_request


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult = req["host"], req["rpi_ms"], req["multiplier"]
    out = {}
    with CIPDriver(ip) as driver:
        out["writes"] = pls.write_program(driver)
        status, data = explicit_request.request(driver, pls.GET, 0x01, 1, 5)
        out["identity_status"] = [status, struct.unpack("<H", data[:2])[0] if data else None]
        enip, owner = pls.start_owner(ip, rpi, mult)
        try:
            out["forward_open"] = owner.run(rpi)
            out["words_at_open"] = owner.words()
            out["home"] = pls.home(driver, 150)
            owner.wait_words(lambda d: d[14] != 0, 2.0)
            owner.settle(rpi)
            out["words_after_home"] = owner.words()
        finally:
            out["forward_close"] = owner.close()
            enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
