"""Helpers shared by the kollmorgen_akd_* peers: explicit requests through pycomm3 (UCMM),
and one Class 1 exclusive owner of the AKD's command (101) and response (102) assemblies
through the PyPI `ethernetip` package, with the 64-byte response read back as bytes.

Not a peer itself: the scenario scripts import it (their directory is on sys.path).
"""
import struct
import time

import ethernetip.ethernetip as enip_mod
from ethernetip.ethernetip import EtherNetIP

# Unconnected requests: the AKD scripts send them as akd.raw.
from explicit_request import raw  # noqa: F401

# Its producer never runs faster than this many ms otherwise.
enip_mod.config.UDP_IO_MIN_RPI = 0

CONFIG, COMMAND, RESPONSE = 100, 101, 102
POSITION_CONTROLLER, PARAMETER = 0x25, 0x0F
GET, SET = 0x0E, 0x10
# Control word (manual p.12).
ENABLE, HARD_STOP, SMOOTH_STOP, DIRECTION, RELATIVE, START_BLOCK, LOAD = (
    0x80, 0x20, 0x10, 0x08, 0x04, 0x02, 0x01)
# Status Word 1 (seed page) and 2 (p.15).
ENABLED, HOMED, CUR_DIR, FAULT, IN_POSITION, BLOCK, IN_MOTION = (
    0x80, 0x20, 0x10, 0x08, 0x04, 0x02, 0x01)
LOAD_COMPLETE = 0x80


def command(control=0, ctype=0x00, rtype=0x20, data=0, position=0, velocity=0, accel=0,
            decel=0, attribute=0, map_type=0, param=b"", block=0):
    """A 64-byte command assembly (axis 1 in bits 5-7 of bytes 2-3 when given so)."""
    c = bytearray(64)
    c[0], c[1], c[2], c[3] = control, block, ctype, rtype
    c[4:24] = struct.pack("<iiiii", data, position, velocity, accel, decel)
    c[24:24 + len(param)] = param
    c[32], c[33] = attribute, map_type
    return bytes(c)


def dint(r, i):
    return struct.unpack_from("<i", r, i)[0]


class Owner:
    """The exclusive owner: output data set with `send`, input data read with `read`."""

    serial = 0

    def __init__(self, enip, ip, rpi_ms, multiplier):
        self.rpi_ms, self.multiplier = rpi_ms, multiplier
        self.conn = enip.explicit_conn(ip)
        self.conn.registerSession()
        Owner.serial += 1
        self.conn.conn_serial_num += 100 * Owner.serial
        self.inp = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_INPUT, 64, RESPONSE, self.conn)
        self.out = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_OUTPUT, 64, COMMAND, self.conn)

    def open(self, multicast=False, rpi_ms=None):
        """Forward_Open (0 on success, else the extended status); starts producing."""
        rpi = rpi_ms or self.rpi_ms
        status = self.conn.sendFwdOpenReq(RESPONSE, COMMAND, CONFIG, torpi=rpi, otrpi=rpi,
                                          multiplier=self.multiplier, multicast=multicast)
        if status == 0:
            self.conn.produce()
        return status

    def send(self, data):
        for i, byte in enumerate(data):
            for b in range(8):
                self.out[i * 8 + b] = bool(byte & (1 << b))

    def read(self):
        """The response, read twice until two reads agree (not torn by the receiver)."""
        for _ in range(100):
            a, b = self._bits(), self._bits()
            if a == b:
                return a
            time.sleep(0.0005)
        return self._bits()

    def _bits(self):
        bits = self.inp
        return bytes(sum(1 << b for b in range(8) if bits[i * 8 + b])
                     for i in range(len(bits) // 8))

    def exchange(self, data, settle_ms=60):
        """Sends `data`, then waits a few RPIs for the response to reflect it."""
        self.send(data)
        time.sleep(settle_ms / 1000.0)
        return self.read()

    def wait_for(self, predicate, seconds):
        """Waits (bounded) until `predicate(response)` holds; the ms it took, or None."""
        t0 = time.monotonic()
        while time.monotonic() - t0 < seconds:
            if predicate(self.read()):
                return (time.monotonic() - t0) * 1000.0
            time.sleep(0.002)
        return None

    def close(self):
        self.conn.stopProduce()
        time.sleep(0.02)
        return self.conn.sendFwdCloseReq(RESPONSE, COMMAND, CONFIG)

    def release(self):
        """Ends the session and its TCP connection (the board serves a few at a time)."""
        self.conn.unregisterSession()
        self.conn.sock.close()
