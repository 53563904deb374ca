"""Blind data injection into an encapsulation session (RFC 5961 section 5): a client opens a
TCP connection to the board's port 44818 and registers a session; a raw segment forged as
the client's, at the client's next sequence number (as an attacker who guessed it would
send) but acknowledging a number far older than any window the client offered, carries a
ListServices request; then the client sends a ListIdentity request of its own and reads
one reply. A board that takes the forged data answers ListServices into the client's
stream first; one that follows RFC 5961 5.2 drops it and answers with an ACK.

The sequence numbers come from an AF_PACKET socket on the interface towards the board,
which sees both directions of the connection.

Reads {"target": str, "older_by": int} as JSON on stdin. Prints one JSON line:
{"reply_command", "forged_answered", "challenge_ack", "board_acks"}: the command of the
first reply the client read, whether the board's stream carried a ListServices reply,
whether the board sent a pure ACK at the client's next sequence number after the forged
segment, and the acknowledgment numbers of the board's segments after it, relative to that
next sequence number.
"""
import json
import socket
import struct
import subprocess
import sys
import time

from tcp_segment import ipv4_tcp

req = json.load(sys.stdin)
target = req["target"]
port = 44818
LIST_SERVICES, LIST_IDENTITY, REGISTER = 0x0004, 0x0063, 0x0065


def header(command, length=0, session=0):
    return struct.pack("<HHII8sI", command, length, session, 0, b"inject!!", 0)


def interface_to(address):
    out = subprocess.run(["ip", "-o", "route", "get", address], capture_output=True,
                         text=True, check=True).stdout.split()
    return out[out.index("dev") + 1]


def segments(raw, until):
    """Every TCP segment of the connection seen until `until`: (from_client, eth, seq, ack,
    flags, payload)."""
    seen = []
    while time.monotonic() < until:
        raw.settimeout(max(0.01, until - time.monotonic()))
        try:
            frame = raw.recv(2048)
        except socket.timeout:
            break
        if len(frame) < 54 or frame[12:14] != b"\x08\x00" or frame[23] != 6:
            continue
        ihl = (frame[14] & 0x0F) * 4
        total = struct.unpack("!H", frame[16:18])[0]
        src, dst = socket.inet_ntoa(frame[26:30]), socket.inet_ntoa(frame[30:34])
        tcp = frame[14 + ihl:14 + total]
        sport, dport, seq, ack, off, flags = struct.unpack("!HHIIBB", tcp[:14])
        payload = tcp[(off >> 4) * 4:]
        if (src, sport, dst, dport) == (me[0], me[1], target, port):
            seen.append((True, frame[:14], seq, ack, flags, payload))
        elif (src, sport, dst, dport) == (target, port, me[0], me[1]):
            seen.append((False, frame[:14], seq, ack, flags, payload))
    return seen


raw = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(0x0003))
raw.bind((interface_to(target), 0))
client = socket.create_connection((target, port), timeout=5)
me = client.getsockname()
def receive(n):
    data = b""
    while len(data) < n:
        chunk = client.recv(n - len(data))
        if not chunk:
            break
        data += chunk
    return data


client.sendall(header(REGISTER, 4) + struct.pack("<HH", 1, 0))
registered = receive(28)
assert len(registered) == 28, registered
session = struct.unpack("<I", registered[4:8])[0]
time.sleep(0.2)
seen = segments(raw, time.monotonic() + 0.3)
mine = [s for s in seen if s[0]]
theirs = [s for s in seen if not s[0]]
last = mine[-1]
client_next = (last[2] + len(last[5]) + (1 if last[4] & 0x01 else 0)) & 0xFFFFFFFF
board = theirs[-1]
board_next = (board[2] + len(board[5])) & 0xFFFFFFFF
client_eth = last[1]

# The forged segment: the client's addresses and next sequence number, an old ACK.
payload = header(LIST_SERVICES, 0, session)
old_ack = (board_next - req["older_by"]) & 0xFFFFFFFF
src_ip, dst_ip = socket.inet_aton(me[0]), socket.inet_aton(target)
packet = ipv4_tcp(src_ip, dst_ip, (me[1], port), client_next, old_ack, 0x18, 0x4242, payload)
raw.send(client_eth + packet)
after = segments(raw, time.monotonic() + 0.3)
board_after = [s for s in after if not s[0]]
acks = [((s[3] - client_next) & 0xFFFFFFFF) for s in board_after]
challenge = any(not s[5] and s[3] == client_next for s in board_after)

client.sendall(header(LIST_IDENTITY))
client.settimeout(3)
reply = receive(24)
command = struct.unpack("<H", reply[:2])[0]
forged_answered = command == LIST_SERVICES
client.close()
print(json.dumps({"reply_command": command, "forged_answered": forged_answered,
                  "challenge_ack": challenge, "board_acks": acks}))
