"""The example I/O block (examples/io-block) read and written by pycomm3 (UCMM): its
identity, and its vendor class 0x70 (channel name, debounce, edge counter, the clear
service 0x4B), as a PLC engineer would with the README's numbers.

Reads {"host"} on stdin. Prints one JSON line of named results, each a general status and
the reply data in hex.
"""
import json
import sys

from pycomm3 import CIPDriver

from explicit_request import raw

CHANNEL = 0x70


def main():
    host = json.load(sys.stdin)["host"]
    r = {}
    with CIPDriver(host) as d:
        r["product_name"] = raw(d, 0x0E, 0x01, 1, 7)
        r["vendor_id"] = raw(d, 0x0E, 0x01, 1, 1)
        r["set_name"] = raw(d, 0x10, CHANNEL, 3, 3, bytes([5]) + b"valve")
        r["name"] = raw(d, 0x0E, CHANNEL, 3, 3)
        r["set_debounce"] = raw(d, 0x10, CHANNEL, 3, 1, bytes([20]))
        r["debounce_too_long"] = raw(d, 0x10, CHANNEL, 3, 1, bytes([101]))
        r["edges_read_only"] = raw(d, 0x10, CHANNEL, 3, 2, bytes(4))
        r["channel_all"] = raw(d, 0x01, CHANNEL, 3, None)
        r["class_max_instance"] = raw(d, 0x0E, CHANNEL, 0, 2)
        r["no_channel_17"] = raw(d, 0x0E, CHANNEL, 17, 1)
        # Outputs written explicitly loop back into the inputs; the edge counter sees it.
        r["set_outputs"] = raw(d, 0x10, 0x04, 150, 3, bytes([0x08, 0x00]))
        r["inputs"] = raw(d, 0x0E, 0x04, 100, 3)
        r["edges_3"] = raw(d, 0x0E, CHANNEL, 4, 2)
        r["clear_edges"] = raw(d, 0x4B, CHANNEL, 4, None)
        r["edges_3_cleared"] = raw(d, 0x0E, CHANNEL, 4, 2)
    print(json.dumps(r))


if __name__ == "__main__":
    main()
