"""EIPScanner (C++, through the PyPI `eip2nats` bridge) as the originator of an input-only
Class 1 connection to the generic profile: configuration 151, heartbeat 152 (O->T: the
sequence count and the 32-bit run/idle header EIPScanner always sends), inputs 100 (T->O: 32
bytes). The bridge publishes every T->O datagram (sequence count, then data) to a
`nats-server` this script runs on the namespace's loopback; the script reads them back
with the NATS text protocol. Half-way, pycomm3 writes output assembly 150, which the
generic profile's input assembly 100 echoes: the new bytes must show up in the T->O data.

Reads {"host", "rpi_us", "seconds", "pattern"} on stdin. Prints one JSON line.
"""
import json
import os
import shutil
import socket
import subprocess
import sys
import time

import eip2nats
from pycomm3 import CIPDriver

import explicit_request

NATS_PORT = 4222
SUBJECT = "enip.t2o"


def nats_server():
    """A nats-server on 127.0.0.1 and a subscriber connected to it (bounded wait)."""
    binary = shutil.which("nats-server") or "/usr/sbin/nats-server"
    server = subprocess.Popen([binary, "-a", "127.0.0.1", "-p", str(NATS_PORT)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 5
    while True:
        try:
            sub = socket.create_connection(("127.0.0.1", NATS_PORT), timeout=1)
            break
        except OSError:
            if time.monotonic() > deadline:
                server.kill()
                raise
            time.sleep(0.05)
    sub.recv(4096)  # INFO
    sub.sendall(f'CONNECT {{"verbose":false}}\r\nSUB {SUBJECT} 1\r\n'.encode())
    sub.settimeout(0.1)
    return server, sub


class Messages:
    """NATS MSG payloads as they arrive on `sub`."""

    def __init__(self, sub):
        self.sub, self.buf, self.payloads = sub, b"", []

    def pump(self, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            try:
                self.buf += self.sub.recv(65536)
            except socket.timeout:
                continue
            self._split()

    def _split(self):
        while True:
            i = self.buf.find(b"\r\n")
            if i < 0:
                return
            line = self.buf[:i]
            if line.startswith(b"MSG "):
                n = int(line.split()[-1])
                if len(self.buf) < i + 2 + n + 2:
                    return
                self.payloads.append(self.buf[i + 2:i + 2 + n])
                self.buf = self.buf[i + 4 + n:]
                continue
            if line == b"PING":
                self.sub.sendall(b"PONG\r\n")
            self.buf = self.buf[i + 2:]


def main():
    req = json.load(sys.stdin)
    # EIPScanner logs on stdout: it goes to stderr, the JSON to the real stdout.
    out_fd = os.dup(1)
    os.dup2(2, 1)
    host, half = req["host"], req["seconds"] / 2.0
    pattern = bytes.fromhex(req["pattern"])
    out = {}
    server, sub = nats_server()
    bridge = eip2nats.EIPtoNATSBridge(host, f"nats://127.0.0.1:{NATS_PORT}", SUBJECT,
                                      config_assembly=151, o2t_assembly=152,
                                      t2o_assembly=100, t2o_size=len(pattern),
                                      rpi=req["rpi_us"], port=2222,
                                      connection_timeout_multiplier=2)
    try:
        messages = Messages(sub)
        out["started"] = bridge.start()
        messages.pump(half)
        out["before_write"] = len(messages.payloads)
        with CIPDriver(host) as driver:
            out["write"] = explicit_request.request(driver, 0x10, 0x04, 150, 3, pattern)[0]
        messages.pump(half)
        bridge.stop()
        messages.pump(0.2)
        payloads = messages.payloads
        sequences = [int.from_bytes(p[:2], "little") for p in payloads]
        out["received"] = bridge.get_received_count()
        out["published"] = bridge.get_published_count()
        out["messages"] = len(payloads)
        out["lengths"] = sorted({len(p) for p in payloads})
        out["gaps"] = sum(1 for a, b in zip(sequences, sequences[1:]) if b != (a + 1) & 0xFFFF)
        out["first_data"] = payloads[0][2:].hex() if payloads else None
        out["last_data"] = payloads[-1][2:].hex() if payloads else None
        seen = [i for i, p in enumerate(payloads) if p[2:] == pattern]
        out["pattern_from"] = seen[0] if seen else None
        out["pattern_stays"] = bool(seen) and seen == list(range(seen[0], len(payloads)))
    finally:
        if bridge.is_running():
            bridge.stop()
        sub.close()
        server.kill()
        server.wait(timeout=5)
    os.write(out_fd, (json.dumps(out) + "\n").encode())


if __name__ == "__main__":
    main()
