"""A storm of Ethernet frames at the board, through an AF_PACKET socket on the namespace's
link: ARP requests for the board's address from changing senders (198.18.0.100-249, each
with its own locally administered MAC), or LLDPDUs from changing chassis (MAC addresses),
at most "per_second" frames a second (a TAP has no line rate of its own), bounded by time
and count.

Reads {"iface": str, "kind": "arp"|"lldp", "seconds": float, "max_frames": int,
"per_second": float, "target": str} as JSON from stdin. Prints one JSON line: {"kind", "frames", "seconds",
"frames_per_second"}.
"""
import json
import socket
import struct
import sys
import time

req = json.load(sys.stdin)
s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW)
s.bind((req["iface"], 0))
target = socket.inet_aton(req["target"])


def mac(i):
    return bytes([0x02, 0xEE, 0, (i >> 16) & 0xFF, (i >> 8) & 0xFF, i & 0xFF])


def arp(i):
    src = mac(i)
    sender_ip = bytes([198, 18, 0, 100 + i % 150])
    body = struct.pack("!HHBBH", 1, 0x0800, 6, 4, 1) + src + sender_ip + bytes(6) + target
    return b"\xff" * 6 + src + b"\x08\x06" + body + bytes(18)


def tlv(kind, value):
    return struct.pack("!H", (kind << 9) | len(value)) + value


def lldp(i):
    src = mac(i)
    body = (tlv(1, b"\x04" + src) + tlv(2, b"\x07" + b"port%d" % (i % 8))
            + tlv(3, struct.pack("!H", 120)) + tlv(0, b""))
    return b"\x01\x80\xc2\x00\x00\x0e" + src + b"\x88\xcc" + body


make = arp if req["kind"] == "arp" else lldp
# A few thousand different senders, built before the clock starts.
frames = [make(i) for i in range(4096)]
start = time.monotonic()
end = start + req["seconds"]
sent = 0
limit = req["max_frames"]
rate = req["per_second"]
i = 0
while sent < limit and time.monotonic() < end:
    # Paced a batch at a time: ahead of the rate, wait until it catches up.
    ahead = sent / rate - (time.monotonic() - start)
    if ahead > 0:
        time.sleep(ahead)
    for _ in range(min(256, limit - sent)):
        try:
            s.send(frames[i])
            sent += 1
        except OSError:  # a full queue: not sent
            pass
        i = (i + 1) % len(frames)
took = time.monotonic() - start
print(json.dumps({"kind": req["kind"], "frames": sent, "seconds": took,
                  "frames_per_second": round(sent / took) if took else 0}))
