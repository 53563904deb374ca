"""The 7500 PLS input functions and network status of issue 25 over the wire: the PyPI
`ethernetip` package owns the I/O and drives soft input 9 (output word 7), pycomm3 programs
the inputs and moves group 1 with home offsets (class 0xC1 attribute 36).

- reset to preset group (average, 2 positions): inputs at 100, 110, 120, 120, 120 leave
  group 1 at 100, 105, 115, 120, 120;
- reset to preset (standard) without an output mask, then with a mask covering both
  outputs of group 1: each time the group position becomes the preset;
- input 9 reconfigured as output enable: its input offset (0xC0/3 word 17) is back to 0;
- network status: the owner stops producing (its connection times out), a Class 3
  connection opens and closes, then the owner opens again; later the owner times out again
  and an Identity Reset (type 0) follows. The board log shows the NS transitions.

Reads {"host", "rpi_ms", "multiplier"} on stdin. Prints one JSON line.
"""
import json
import sys
import time

from pycomm3 import CIPDriver

import ametek_pls_common as pls
import explicit_request


def inputs(word_list):
    """Attribute 34 with input 9 set to `word_list` (7 words)."""
    w = [0] * 112
    w[56:63] = word_list
    return w


def edge(owner, rpi):
    """A rising edge of soft input 9 (low, then high), each level settled."""
    for level in (0, 1):
        owner.send([pls.RUN, 0, 0, 0, 0, 0, level])
        owner.settle(rpi)


def timeout(owner, rpi, mult):
    """Stops producing without a Forward_Close and waits past the watchdog."""
    owner.conn.stopProduce()
    time.sleep(4 * (4 << mult) * rpi / 1000.0 + 0.2)


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult = req["host"], req["rpi_ms"], req["multiplier"]
    out = {}
    with CIPDriver(ip) as driver:
        out["writes"] = pls.write_program(driver)
        enip, owner = pls.start_owner(ip, rpi, mult)
        try:
            out["forward_open"] = owner.run(rpi)
            out["average_write"] = pls.set_words(driver, 34, inputs([1, 0, 0, 122, 2, 0, 0]))
            average = []
            for at in (100, 110, 120, 120, 120):
                pls.home(driver, at)
                edge(owner, rpi)
                average.append(owner.words()[0])
            out["average"] = average
            # No output mask (2.6: "used to reset the position of a PLS group"): the group.
            pls.home(driver, 250)
            out["no_mask_write"] = pls.set_words(driver, 34, inputs([1, 0, 0, 20, 55, 0, 0]))
            edge(owner, rpi)
            out["no_mask"] = owner.words()[0]
            pls.home(driver, 250)
            out["whole_write"] = pls.set_words(
                driver, 34, inputs([1, 0x0001, 0x0001, 20, 55, 0, 0]))
            edge(owner, rpi)
            w = owner.words()
            out["whole"] = [w[0], w[10] & 1, w[11] & 1]
            out["offset_before"] = pls.get_words(driver, pls.STATUS, 3)[16]
            out["enable_write"] = pls.set_words(driver, 34, inputs([1, 0, 0, 130, 0, 0, 0]))
            out["offset_after"] = pls.get_words(driver, pls.STATUS, 3)[16]
            timeout(owner, rpi, mult)
            owner._stop.set()
            # A Class 3 connection opens and closes: no re-establishment.
            # (pycomm3 opens the connection for the connected request.)
            out["class3_get"] = explicit_request.request(driver, pls.GET, 0x01, 1, 1,
                                                         connected=True)[0]
            out["class3_close"] = driver._forward_close()
            time.sleep(0.2)
            # The owner opens again (same originator and points): every timed-out
            # connection is back.
            owner = pls.Owner(enip, ip, rpi, mult, owner.t0)
            out["reopen"] = owner.run(rpi)
            time.sleep(0.2)
            timeout(owner, rpi, mult)
        finally:
            owner._stop.set()
            enip.stopIO()
        out["identity_reset"] = explicit_request.request(driver, 0x05, 0x01, 1, None,
                                                         b"\x00")[0]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
