"""Helpers shared by the position_servo_* peers: the PositionServo's System940 variables
(class 0x64) through pycomm3 explicit messages, and Class 1 connections through the PyPI
`ethernetip` package with their input data sampled over time.

Not a peer itself: the scenario scripts import it (their directory is on sys.path).
"""
import struct
import threading
import time

import ethernetip.ethernetip as enip_mod
from ethernetip.ethernetip import EtherNetIP

import explicit_request

# Its producer never runs faster than this many ms otherwise.
enip_mod.config.UDP_IO_MIN_RPI = 0

SYSTEM940 = 0x64
GET, SET = 0x0E, 0x10
# Attributes: integer, REAL, string; each RAM (even) and EPM (odd).
INT_RAM, INT_EPM, REAL_RAM, REAL_EPM, TEXT_RAM, TEXT_EPM = range(6)
# Assemblies (manual tables 14-21) and the heartbeat point of input-only connections.
CONFIG, STATUS_IO, MONITOR, BASIC, KEEP_ALIVE, INPUT_ONLY = 103, 104, 105, 106, 109, 198


def request(driver, service, var, attribute, data=b""):
    """One UCMM request to variable `var`; returns (general status or None, reply bytes)."""
    return explicit_request.request(driver, service, SYSTEM940, var, attribute, data)


def set_real(driver, var, value, attribute=REAL_RAM):
    return request(driver, SET, var, attribute, struct.pack("<f", value))[0]


def set_int(driver, var, value, attribute=INT_RAM):
    return request(driver, SET, var, attribute, struct.pack("<I", value & 0xFFFFFFFF))[0]


def get_real(driver, var):
    status, data = request(driver, GET, var, REAL_RAM)
    return struct.unpack("<f", data)[0] if status == 0 and len(data) == 4 else None


def get_int(driver, var):
    status, data = request(driver, GET, var, INT_RAM)
    return struct.unpack("<I", data)[0] if status == 0 and len(data) == 4 else None


def words(data, fmt):
    """Little-endian 32-bit words of `data` as `fmt` ("f" or "I")."""
    return list(struct.unpack("<" + fmt * (len(data) // 4), data[: len(data) // 4 * 4]))


class Class1:
    """One Class 1 connection of `ethernetip`: output data set with `write`, input data
    sampled in the background (time in ms since `t0`, data) whenever it changes."""

    opened = 0

    def __init__(self, enip, ip, inp, in_size, out, out_size, rpi_ms, multiplier, t0):
        self.points = (inp, out, CONFIG)
        self.rpi_ms, self.multiplier, self.t0 = rpi_ms, multiplier, t0
        self.conn = enip.explicit_conn(ip)
        self.conn.registerSession()
        # Every connection of this originator needs its own connection serial number.
        Class1.opened += 1
        self.conn.conn_serial_num += 100 * Class1.opened
        self.inp = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_INPUT, in_size, inp, self.conn)
        self.out = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_OUTPUT, out_size, out, self.conn)
        self.samples = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._sample, daemon=True)

    def open(self):
        """Forward_Open (0 on success, else the extended status); starts producing."""
        inp, out, config = self.points
        status = self.conn.sendFwdOpenReq(inp, out, config, torpi=self.rpi_ms,
                                          otrpi=self.rpi_ms, multiplier=self.multiplier)
        if status == 0:
            self.conn.produce()
            self._thread.start()
        return status

    def write(self, data):
        for i, byte in enumerate(data):
            for b in range(8):
                self.out[i * 8 + b] = bool(byte & (1 << b))

    def read(self):
        bits = self.inp
        return bytes(sum(1 << b for b in range(8) if bits[i * 8 + b])
                     for i in range(len(bits) // 8))

    def _sample(self):
        last = None
        while not self._stop.is_set():  # bounded by close()
            data = self.read()
            # Two equal reads in a row: not torn by the receiving thread.
            if data == self.read() and data != last:
                self.samples.append(((time.monotonic() - self.t0) * 1000.0, data))
                last = data
            time.sleep(0.0005)

    def wait_for(self, predicate, seconds):
        """Waits (bounded) until `predicate(data)` holds for the input; returns the time in ms
        since t0, or None."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            data = self.read()
            if data == self.read() and predicate(data):
                return (time.monotonic() - self.t0) * 1000.0
            time.sleep(0.0005)
        return None

    def close(self):
        self._stop.set()
        self.conn.stopProduce()
        time.sleep(0.02)
        inp, out, config = self.points
        return self.conn.sendFwdCloseReq(inp, out, config)


def control(enable, reference):
    """Assembly 106 data: DRIVE ENABLE and REFERENCE as REALs."""
    return struct.pack("<ff", enable, reference)


def slope(points):
    """Least-squares slope of (t_ms, value) points, per second."""
    n = len(points)
    if n < 2:
        return None
    mt = sum(t for t, _ in points) / n
    mv = sum(v for _, v in points) / n
    den = sum((t - mt) ** 2 for t, _ in points)
    return None if den == 0 else 1000.0 * sum((t - mt) * (v - mv) for t, v in points) / den
