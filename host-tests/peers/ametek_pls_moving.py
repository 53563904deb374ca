"""The 7500 PLS with a moving simulated resolver (board option --pls-rpm): the PyPI
`ethernetip` package owns the I/O at the given RPI and samples the input data; pycomm3
programs outputs 1 and 17 first.

Reads {"host", "rpi_ms", "multiplier", "seconds"} on stdin. Prints one JSON line with every
distinct sample as [t_ms, group 1 position, RPM, output status 1-16, 17-32].
"""
import json
import sys
import time

from pycomm3 import CIPDriver

import ametek_pls_common as pls


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult = req["host"], req["rpi_ms"], req["multiplier"]
    out = {}
    with CIPDriver(ip) as driver:
        out["writes"] = pls.write_program(driver)
        enip, owner = pls.start_owner(ip, rpi, mult)
        try:
            out["forward_open"] = owner.run(rpi)
            owner.samples.clear()
            time.sleep(req["seconds"])
            out["samples"] = [[round(t, 1)] + [pls.words(d)[i] for i in (0, 8, 10, 11)]
                              for t, d in list(owner.samples)]
        finally:
            out["forward_close"] = owner.close()
            enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
