"""The 7500 PLS classes with pycomm3 (explicit messages, as the manual's §3.2 MSG
instruction) while the PyPI `ethernetip` package owns the I/O (§3.1): every attribute's
size, a valid configuration read back, and each validation rule broken once: its CIP status,
and input words 15-17 over Class 1, which a later valid write leaves and only an
Acknowledge 0->1 clears.

Reads {"host", "rpi_ms", "multiplier", "cases": [{"name", "attribute", "words"}]} on stdin.
Prints one JSON line.
"""
import json
import sys

from pycomm3 import CIPDriver

import ametek_pls_common as pls


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult = req["host"], req["rpi_ms"], req["multiplier"]
    out = {"sizes": {}}
    with CIPDriver(ip) as driver:
        for a in (1, 2, 3):
            status, data = pls.request(driver, pls.GET, pls.STATUS, a)
            out["sizes"][f"C0/{a}"] = [status, len(data)]
        for a in range(1, 39):
            status, data = pls.request(driver, pls.GET, pls.CONFIG, a)
            out["sizes"][f"C1/{a}"] = [status, len(data)]
        # Writes of every writable attribute with the manual's size, read back.
        config = {1: pls.pls_object(), 2: pls.output_1(), 18: pls.output_17()}
        inputs = [0] * 112
        inputs[56:63] = [0b011, 0, 0, 120, 77, 0, 0]
        config[34] = inputs
        config[35] = [60, 1500, 0x0001]
        out["writes"] = {a: pls.set_words(driver, a, w) for a, w in config.items()}
        out["readback"] = {a: pls.request(driver, pls.GET, pls.CONFIG, a)[1] == pls.le(w)
                           for a, w in config.items()}
        for a in list(range(3, 18)) + list(range(19, 34)):
            data = pls.request(driver, pls.GET, pls.CONFIG, a)[1]
            out.setdefault("others", []).append(
                [a, pls.request(driver, pls.SET, pls.CONFIG, a, data)[0]])
        enip, owner = pls.start_owner(ip, rpi, mult)
        try:
            out["forward_open"] = owner.run(rpi)
            out["error_at_open"] = owner.words()[14:17]
            results = []
            for case in req["cases"]:
                a, w = case["attribute"], case["words"]
                before = pls.request(driver, pls.GET, pls.CONFIG, a)[1]
                status = pls.request(driver, pls.SET, pls.CONFIG, a, pls.le(w))[0]
                seen = owner.wait_words(lambda d: d[14] != 0, 2.0)
                owner.settle(rpi)
                latched = owner.words()[14:17]
                unchanged = pls.request(driver, pls.GET, pls.CONFIG, a)[1] == before
                # A later valid write leaves the words.
                valid = pls.set_words(driver, 35, [60, 1500, 0x0001])
                owner.settle(rpi)
                after_valid = owner.words()[14:17]
                # Acknowledge 0 -> 1 clears them.
                owner.send([pls.RUN | pls.ACK])
                cleared = owner.wait_words(lambda d: d[14:17] == [0, 0, 0], 2.0)
                owner.send([pls.RUN])
                owner.settle(rpi)
                results.append({"name": case["name"], "status": status, "seen": seen is not None,
                                "words": latched, "unchanged": unchanged, "valid": valid,
                                "after_valid": after_valid, "cleared": cleared is not None})
            out["cases"] = results
        finally:
            out["forward_close"] = owner.close()
            enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
