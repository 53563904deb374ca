"""Program control (§2.9) with pycomm3: phase "save" programs the PLS, saves it (code 2),
changes output 1 and restores (code 3); phase "check" (after a restart of the board with
the same non-volatile file) reads the program back.

Reads {"host", "phase"} on stdin. Prints one JSON line with the attributes as hex.
"""
import json
import sys

from pycomm3 import CIPDriver

import ametek_pls_common as pls


def snapshot(driver):
    return {a: pls.request(driver, pls.GET, pls.CONFIG, a)[1].hex() for a in (1, 2, 18)}


def main():
    req = json.load(sys.stdin)
    out = {}
    with CIPDriver(req["host"]) as driver:
        if req["phase"] == "save":
            out["writes"] = pls.write_program(driver) + [pls.home(driver, 150)]
            out["save"] = pls.set_words(driver, 37, [2, 0])
            out["saved"] = snapshot(driver)
            changed = pls.output_1()
            changed[8] = 10
            out["change"] = pls.set_words(driver, 2, changed)
            out["changed"] = snapshot(driver)
            out["restore"] = pls.set_words(driver, 37, [3, 0])
            out["control_readback"] = pls.get_words(driver, pls.CONFIG, 37)
        out["restored"] = snapshot(driver)
        out["offsets"] = pls.get_words(driver, pls.STATUS, 3)[:8]
        out["expected"] = {1: pls.le(pls.pls_object()).hex(), 2: pls.le(pls.output_1()).hex(),
                           18: pls.le(pls.output_17()).hex()}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
