"""The Parker IPA's axes and Write Binary with pycomm3 (UCMM and Class 3): the manual's
figure 4 jog-profile write starts nothing; a binary SET of axis 0's jog forward bit
(bit 8464 = P4360 bit 16) moves it and sets jog active (bit 18), CLR stops it; the ACR
binary Set Long, Set IEEE and Parameter Mask commands; unsupported and truncated commands
refused with nothing changed.

Reads {"host"} on stdin. Prints one JSON line of named results.
"""
import json
import struct
import sys
import time

from pycomm3 import CIPDriver

import parker_ipa_common as ipa
from parker_ipa_common import GROUP, PARAMETER, WRITE_BINARY, WRITE_FLOATS, floats, request


def binary(d, packet):
    """One Write Binary request over the Class 3 connection; its general status."""
    return request(d, WRITE_BINARY, GROUP, 1, bytes(packet), connected=True)[0]


def index(p):
    return list(struct.pack("<H", p))


def main():
    host = json.load(sys.stdin)["host"]
    out = {}
    with CIPDriver(host) as d:
        # Figure 4: the jog profile of axis 0 (VEL 15), then 0.5 s: nothing moves.
        out["fig4_write"] = request(d, WRITE_FLOATS, PARAMETER, 12348,
                                    floats([15.0, 150.0, 125.0, 625.0]))[0]
        before = ipa.read_longs(d, 12288, 3)
        time.sleep(0.5)
        out["fig4_positions"] = [before, ipa.read_longs(d, 12288, 3)]
        out["fig4_flags"] = ipa.read_longs(d, 4360, 1)
        # Binary SET bit 8464 (jog forward, axis 0) over Class 3: the axis moves.
        out["set_jog"] = binary(d, [0x1C] + index(8464))
        time.sleep(0.5)
        out["jog_flags"] = ipa.read_longs(d, 4360, 1)
        out["jog_position"] = ipa.read_longs(d, 12288, 1)
        # Binary CLR: it stops, jog active clears.
        out["clr_jog"] = binary(d, [0x1D] + index(8464))
        time.sleep(0.05)
        stopped = ipa.read_longs(d, 12288, 1)
        time.sleep(0.3)
        out["stopped_positions"] = stopped + ipa.read_longs(d, 12288, 1)
        out["stopped_flags"] = ipa.read_longs(d, 4360, 1)
        # Set Long P38912 = -7 and Set IEEE P39168 = 2.5 in one request.
        out["set_long_ieee"] = binary(d, [0x00, 0x89] + index(38912) + list(struct.pack("<i", -7))
                                      + [0x00, 0x8B] + index(39168)
                                      + list(struct.pack("<f", 2.5)))
        out["set_long_value"] = ipa.read_longs(d, 38912, 1)
        out["set_ieee_value"] = ipa.read_floats(d, 39168, 1)
        # Parameter Mask on P4097: clear all, set bit 0 (the Guide's example).
        ipa.write_longs(d, 4097, [0x7F00])
        out["mask"] = binary(d, [0x00, 0x95] + index(4097) + [0xFF] * 4 + [1, 0, 0, 0])
        out["mask_value"] = ipa.read_longs(d, 4097, 1)
        # Refused: Get Long (Table 7 "No"), FOV (not simulated), a cut-short Set Long, a
        # Set Long to P10 (does not exist), each after a good Set Long of P38912 = 99.
        good = [0x00, 0x89] + index(38912) + [99, 0, 0, 0]
        out["refused"] = [
            binary(d, good + [0x00, 0x88] + index(38912)),
            binary(d, good + [0x07, 0x01, 0, 0, 0, 0, 0x80, 0x3F]),
            binary(d, good + [0x00, 0x89, 0x00]),
            binary(d, good + [0x00, 0x89] + index(10) + [0, 0, 0, 0]),
        ]
        out["refused_value"] = ipa.read_longs(d, 38912, 1)
        out["ucmm"] = request(d, WRITE_BINARY, GROUP, 1, bytes(good))[0]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
