"""Tag services of the Parker IPA ("P4012" symbolic paths, Table 5) with cpppo's client:
0x4C Read Tag and 0x4D Write Tag of both types, and the class 0x64 services (pycomm3) reading
and writing the same parameters.

Reads {"host"} on stdin. Prints one JSON line of named results.
"""
import json
import struct
import sys

from cpppo.server.enip import client
from cpppo.server.enip.parser import DINT, REAL
from pycomm3 import CIPDriver

import parker_ipa_common as ipa


def op(name, elements=1, values=None, kind=None):
    """A cpppo operation on tag `name` (no element segment: the element count is the data)."""
    o = {"path": [{"symbolic": name}], "elements": elements, "route_path": False,
         "send_path": ""}
    if values is not None:
        o.update(method="write", data=values, tag_type=kind.tag_type)
    return o


def run(conn, ops):
    out = []
    for _, _, _, _, status, value in conn.synchronous(operations=client.parse_operations(ops)):
        out.append({"status": status, "value": value if isinstance(value, list) else None})
    return out


def main():
    host = json.load(sys.stdin)["host"]
    res = {}
    with CIPDriver(host) as d:
        ipa.write_longs(d, 4112, [7, -8, 9])
        ipa.write_floats(d, 39202, [99.75])
        with client.connector(host=host, timeout=5) as conn:
            r = run(conn, [
                op("P4112", 3),                       # Figure 1
                op("P4100", 1, [0x0BADCAFE], DINT),   # Figure 2
                op("P39001", 1, [77.0], REAL),        # REAL to a long
                op("P39201", 1, [-3], DINT),          # DINT to a float
                op("P39202", 1),                      # a float read as DINT
                op("P38920", 4, [1, 2, 3, 4], DINT),
                op("P39300", 2, [1.5, -2.25], REAL),
                op("P4096", 17),                      # case 3
                op("P10", 1),                         # no such parameter
            ])
        res["cpppo"] = r
        res["p4112_by_0x53"] = ipa.read_longs(d, 4112, 3)
        res["p4100_by_0x53"] = ipa.read_longs(d, 4100, 1)
        res["p39001_by_0x53"] = ipa.read_longs(d, 39001, 1)
        res["p39201_by_0x51"] = ipa.read_floats(d, 39201, 1)
        res["p38920_by_0x53"] = ipa.read_longs(d, 38920, 4)
        res["p39300_by_0x51"] = ipa.read_floats(d, 39300, 2)
    print(json.dumps(res))


if __name__ == "__main__":
    main()
