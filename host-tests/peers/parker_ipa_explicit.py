"""The Parker IPA manual's explicit examples with pycomm3, unconnected (UCMM) and over a
Class 3 connection: Figures 4/5 (jog write), 6/7 (axis flags read), 8/9 (AND/OR), 10 (group
read), the conversion of p.23, the binary command over Class 3, and every error case of
Table 8 with its general status.

Reads {"host"} on stdin. Prints one JSON line of named results: lists of values, or
{"status", "data"} for raw requests.
"""
import json
import sys

from pycomm3 import CIPDriver

import parker_ipa_common as ipa
from parker_ipa_common import (AND_OR, GROUP, PARAMETER, READ_FLOATS, READ_LONGS,
                               WRITE_BINARY, WRITE_FLOATS, WRITE_LONGS, floats, longs, request,
                               result)


def main():
    host = json.load(sys.stdin)["host"]
    out = {}
    with CIPDriver(host) as d:
        # Figures 4/5: WriteACRFloat to P12348, read back with 0x51.
        out["fig4_write"] = result(request(d, WRITE_FLOATS, PARAMETER, 12348,
                                           floats([15.0, 150.0, 125.0, 625.0])))
        out["fig4_readback"] = ipa.read_floats(d, 12348, 4)
        # Figures 6/7: ReadACRLong_AxisFlags, P4360 count 3.
        out["fig6_read"] = result(request(d, READ_LONGS, PARAMETER, 4360, longs([3])))
        # Figures 8/9: AND/OR on P4111.
        out["fig8_preset"] = ipa.write_longs(d, 4111, [0x12345678])
        out["fig8_and_or"] = result(request(d, AND_OR, PARAMETER, 4111,
                                            longs([-256, 0x55])))
        out["fig8_result"] = ipa.read_longs(d, 4111, 1)
        # p.23: 0x53 on the float P12304.
        out["p23_write"] = ipa.write_floats(d, 12304, [1234.75])
        out["p23_long"] = ipa.read_longs(d, 12304, 1)
        # Figure 10: PGAIN of axes 0-3 by group read (0x65, instance 12304, block 4).
        for k in range(4):
            ipa.write_floats(d, 12304 + 256 * k, [10.5 + k])
        out["fig10_group"] = result(request(d, READ_LONGS, GROUP, 12304, longs([4])))
        # Group 0x30 index 2 (actual positions) against individual reads.
        for k in range(8):
            ipa.write_longs(d, 12290 + 256 * k, [1000 * k - 3])
        out["group_0x30_2"] = result(request(d, READ_LONGS, GROUP, 0x3002, longs([8])))
        out["individual_0x30_2"] = [ipa.read_longs(d, 12290 + 256 * k, 1)[0] for k in range(8)]
        # Attribute absent or another value: the same answer.
        out["no_attribute"] = result(request(d, READ_LONGS, PARAMETER, 4360, longs([3]),
                                             attribute=None))
        out["attribute_7"] = result(request(d, READ_LONGS, PARAMETER, 4360, longs([3]),
                                            attribute=7))
        # Table 8.
        cases = {
            "case1_get_attr": (0x0E, PARAMETER, 4100, b""),
            "case1_0x55": (0x55, PARAMETER, 4100, b""),
            "case1_0x4c_class_path": (0x4C, PARAMETER, 4112, b"\x01\x00"),
            "case1_0x50_on_group": (WRITE_FLOATS, GROUP, 12304, floats([1.0])),
            "case2_binary_ucmm": (WRITE_BINARY, GROUP, 1, b"\x01\x02\x03\x04"),
            "case3_read_longs_17": (READ_LONGS, PARAMETER, 4096, longs([17])),
            "case3_read_floats_17": (READ_FLOATS, PARAMETER, 4096, longs([17])),
            "case4_write_longs_17": (WRITE_LONGS, PARAMETER, 38912, longs([5] * 17)),
            "case4_write_floats_17": (WRITE_FLOATS, PARAMETER, 39168, floats([5.0] * 17)),
            "case5_and_or_4": (AND_OR, PARAMETER, 4111, longs([-1])),
            "case5_and_or_0": (AND_OR, PARAMETER, 4111, b""),
            "case6_block_0": (READ_LONGS, GROUP, 12304, longs([0])),
            "case6_block_9": (READ_LONGS, GROUP, 12304, longs([9])),
            "case7_group_0x80": (READ_LONGS, GROUP, 0x8002, longs([1])),
            "case7_group_0xbf": (READ_LONGS, GROUP, 0xBF00, longs([1])),
            "unknown_p10": (READ_LONGS, PARAMETER, 10, longs([1])),
        }
        for name, (service, cls, instance, data) in cases.items():
            out[name] = result(request(d, service, cls, instance, data))
        out["case4_unchanged"] = ipa.read_longs(d, 38912, 1) + ipa.read_floats(d, 39168, 1)
        out["case5_unchanged"] = ipa.read_longs(d, 4111, 1)
        # Over a Class 3 connection: the binary command, and a read equal to UCMM's.
        # Binary Set Long (00 89, index 0x9800 = P38912) = 5.
        out["c3_binary"] = result(request(d, WRITE_BINARY, GROUP, 1,
                                          b"\x00\x89\x00\x98\x05\x00\x00\x00",
                                          connected=True))
        out["c3_binary_value"] = ipa.read_longs(d, 38912, 1)
        out["c3_read"] = result(request(d, READ_LONGS, PARAMETER, 4360, longs([3]),
                                        connected=True))
        out["c3_stream"] = ipa.read_longs(d, 37424, 1, connected=True)
        out["c3_status"] = ipa.read_longs(d, 37424, 16)
        out["identity_name"] = result(request(d, 0x0E, 0x01, 1, attribute=7))
        out["identity_vendor"] = result(request(d, 0x0E, 0x01, 1, attribute=1))
    print(json.dumps(out))


if __name__ == "__main__":
    main()
