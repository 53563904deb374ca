"""Pipelined requests in one segment, as a client that does not wait for each reply.

Reads one JSON document from stdin:
  {"host": "198.18.0.2", "kind": "list_identity" | "get_attributes_all", "count": int,
   "close_after": bool (optional, default false)}
Registers a session, then sends `count` requests of `kind` (ListIdentity on TCP, or
SendRRData with Get_Attributes_All of Identity instance 1), each with its index as sender
context, in one sendall, and reads every reply (5 s at most). With `close_after`, the
client's FIN follows the burst at once (shutdown for writing), and after the replies it
waits for the adapter's FIN (end of stream, 5 s at most).
Prints one JSON line: {"replies": int, "in_order": bool (sender contexts 0, 1, ...),
"encap_statuses": [int], "cip_statuses": [int] (get_attributes_all only), "seconds": float,
"retransmissions": int (the client socket's tcpi_total_retrans: segments sent again),
"closed": bool (with close_after: the adapter's FIN came after the replies and nothing else),
"seconds_to_close": float (with close_after: from the burst to the adapter's FIN)}.
"""
import json
import socket
import struct
import sys
import time

# struct tcp_info: 8 bytes of u8 fields, then u32 fields; tcpi_total_retrans is the 24th.
TOTAL_RETRANS_OFFSET = 8 + 23 * 4
HEADER = struct.Struct("<HHII8sI")


def request(kind, session, index):
    context = struct.pack("<Q", index)
    if kind == "list_identity":
        return HEADER.pack(0x63, 0, 0, 0, context, 0)
    cip = bytes([0x01, 0x02, 0x20, 0x01, 0x24, 0x01])
    cpf = (struct.pack("<IHH", 0, 0, 2) + struct.pack("<HH", 0, 0)
           + struct.pack("<HH", 0xB2, len(cip)) + cip)
    return HEADER.pack(0x6F, len(cpf), session, 0, context, 0) + cpf


def read_frame(sock, buf):
    while True:
        if len(buf) >= 24:
            length = struct.unpack_from("<H", buf, 2)[0]
            if len(buf) >= 24 + length:
                return buf[:24 + length], buf[24 + length:]
        data = sock.recv(65536)
        if not data:
            raise ConnectionError("closed")
        buf += data


def main():
    spec = json.load(sys.stdin)
    kind, count = spec["kind"], spec["count"]
    sock = socket.create_connection((spec["host"], 44818), timeout=5)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    sock.sendall(HEADER.pack(0x65, 4, 0, 0, b"\0" * 8, 0) + struct.pack("<HH", 1, 0))
    frame, buf = read_frame(sock, b"")
    session = struct.unpack_from("<I", frame, 4)[0]
    burst = b"".join(request(kind, session, i) for i in range(count))
    close_after = spec.get("close_after", False)
    start = time.monotonic()
    sock.sendall(burst)
    if close_after:
        sock.shutdown(socket.SHUT_WR)
    contexts, encap_statuses, cip_statuses = [], [], []
    try:
        for _ in range(count):
            frame, buf = read_frame(sock, buf)
            _, _, _, status, context, _ = HEADER.unpack_from(frame)
            contexts.append(struct.unpack("<Q", context)[0])
            encap_statuses.append(status)
            if kind == "get_attributes_all" and len(frame) >= 24 + 16 + 4:
                # CPF: interface, timeout, count, null item, data item header, then the reply.
                cip_statuses.append(frame[24 + 16 + 2])
    except (socket.timeout, ConnectionError):
        pass
    seconds = time.monotonic() - start
    closed, seconds_to_close = False, None
    if close_after:
        try:
            closed = buf == b"" and sock.recv(65536) == b""
            seconds_to_close = time.monotonic() - start
        except (socket.timeout, ConnectionError):
            pass
    info = sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_INFO, 256)
    retransmissions = struct.unpack_from("<I", info, TOTAL_RETRANS_OFFSET)[0]
    sock.close()
    print(json.dumps({"replies": len(contexts), "in_order": contexts == list(range(len(contexts))),
                      "encap_statuses": encap_statuses, "cip_statuses": cip_statuses,
                      "seconds": seconds, "retransmissions": retransmissions,
                      "closed": closed, "seconds_to_close": seconds_to_close}))


if __name__ == "__main__":
    main()
