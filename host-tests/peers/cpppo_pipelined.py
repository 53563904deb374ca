"""Pipelined attribute reads with cpppo's client proxy: `depth` requests in flight at once.

Reads one JSON document from stdin:
  {"host": "198.18.0.2", "depth": int, "count": int, "path": "@class/instance/attribute",
   "type": "USINT" | ...}
Reads the attribute `count` times through proxy_simple (plain UCMM) with `depth` requests
outstanding, then reads the client socket's TCP counters (Linux TCP_INFO).
Prints one JSON line: {"statuses": [int, ...], "values": [value, ...], "seconds": float,
"retransmissions": int (tcpi_total_retrans: segments the client had to send again)}.
"""
import contextlib
import json
import socket
import struct
import sys
import time

from cpppo.server.enip.get_attribute import proxy_simple

# struct tcp_info: 8 bytes of u8 fields, then u32 fields; tcpi_total_retrans is the 24th.
TOTAL_RETRANS_OFFSET = 8 + 23 * 4


def total_retransmissions(sock):
    info = sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_INFO, 256)
    return struct.unpack_from("<I", info, TOTAL_RETRANS_OFFSET)[0]


def main():
    spec = json.load(sys.stdin)
    via = proxy_simple(spec["host"], timeout=5, depth=spec["depth"])
    statuses, values = [], []
    with via:
        ops = [(spec["path"], spec["type"])] * spec["count"]
        start = time.monotonic()
        with contextlib.closing(via.read_details(ops)) as reader:
            for value, (status, _) in reader:
                statuses.append(status)
                values.append(list(value) if isinstance(value, (list, tuple)) else value)
        seconds = time.monotonic() - start
        retransmissions = total_retransmissions(via.gateway.conn)
    via.close_gateway()
    print(json.dumps({"statuses": statuses, "values": values, "seconds": seconds,
                      "retransmissions": retransmissions}))


if __name__ == "__main__":
    main()
