"""A storm of Ethernet frames at the board, through an AF_PACKET socket on the namespace's
link: ARP requests for the board's address from changing senders (198.18.0.100-249, each
with its own locally administered MAC), LLDPDUs from changing chassis (MAC addresses), or
TCP SYNs ("syn") or ACKs of no connection ("ack") to the board's port 44818 from the same
changing senders and ports (a flood from many forged sources: the board's SYN guard follows
a few sources at a time, and 150 in turn push each other out of it before any counts as a
flooder; the board's MAC is read from this namespace's ARP table), or ICMP echo requests
("echo") from this side's own address ("source") and MAC, which the board knows and so
answers each (a ping flood), at most
"per_second" frames a second (a TAP has no line rate of its own), bounded by time and count.

Reads {"iface": str, "kind": "arp"|"lldp"|"syn"|"ack"|"echo", "seconds": float, "max_frames": int,
"per_second": float, "target": str, "source": str} as JSON from stdin. Prints one JSON line: {"kind", "frames", "seconds",
"frames_per_second"}.
"""
import json
import socket
import struct
import sys
import time

from tcp_segment import checksum, ipv4_tcp

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


def board_mac():
    with open("/proc/net/arp") as table:
        for line in table.readlines()[1:]:
            fields = line.split()
            # A complete entry only (flag 0x2): an incomplete one's MAC is all zeros.
            if fields[0] == req["target"] and int(fields[2], 16) & 0x2:
                return bytes.fromhex(fields[3].replace(":", ""))
    sys.exit("the board's MAC is not in the ARP table")


def syn(i, flags=0x02):
    src_ip = bytes([198, 18, 0, 100 + i % 150])
    ack = 0x2000 * i if flags & 0x10 else 0
    packet = ipv4_tcp(src_ip, target, (1024 + i, 44818), 0x1000 * i, ack, flags, i, mss=1460)
    return to_board + mac(i) + b"\x08\x00" + packet


def echo(i):
    src_ip = socket.inet_aton(req["source"])
    body = struct.pack("!BBHHH", 8, 0, 0, i & 0xFFFF, i >> 16) + bytes(32)
    icmp = body[:2] + struct.pack("!H", checksum(body)) + body[4:]
    ip = struct.pack("!BBHHHBBH4s4s", 0x45, 0, 20 + len(icmp), i & 0xFFFF, 0, 64, 1, 0,
                     src_ip, target)
    packet = ip[:10] + struct.pack("!H", checksum(ip)) + ip[12:] + icmp
    return to_board + own_mac + b"\x08\x00" + packet


kind = req["kind"]
if kind in ("syn", "ack", "echo"):
    to_board = board_mac()
with open("/sys/class/net/%s/address" % req["iface"]) as own:
    own_mac = bytes.fromhex(own.read().strip().replace(":", ""))
make = {"arp": arp, "lldp": lldp, "syn": syn, "ack": lambda i: syn(i, 0x10),
        "echo": echo}[kind]
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
