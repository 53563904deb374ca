"""Class 1 with the Parker IPA profile: the PyPI `ethernetip` package as exclusive owner of
102/101 with configuration point 3 (Generic Ethernet Module style, 400 bytes each way), and
pycomm3 for the explicit side (configuration P37434/P37440.., status P37424-P37439).

Scenario: a 4-group configuration; O->T data lands in the configured parameters; an
explicit write to a produced parameter shows in the T->O data (delay measured); the status
parameters report the connection; a second Class 1 Forward_Open is refused while the first
keeps running (P37429/P37430 still the first client); after Forward_Close P37433 = 0. Then the configuration errors 2, 3, 4, 5 and 7
(each Forward_Open refused, P37433-P37437 read back, the manual's example 2 among them),
RPI 0.5 ms refused either way and 1 ms accepted, a multicast T->O, and the loss of O->T
(the watchdog closes the connection, P37433 = 0, a new Forward_Open succeeds).

Reads {"host", "rpi_ms"} on stdin. Prints one JSON line of named results.
"""
import json
import struct
import sys
import threading
import time

import ethernetip.ethernetip as enip_mod
from ethernetip.ethernetip import EtherNetIP
from pycomm3 import CIPDriver

import parker_ipa_common as ipa

# Its producer never runs faster than this many ms otherwise.
enip_mod.config.UDP_IO_MIN_RPI = 0

INPUT, OUTPUT, CONFIG = 101, 102, 3
SIZE = 400
FOUR_GROUPS = [(38912, 2, 0, 1), (39168, 2, 0, 2), (39000, 3, 1, 1), (39300, 2, 1, 2)]


class Owner:
    """One exclusive-owner connection of `ethernetip` (its own session)."""

    serial = 0

    def __init__(self, enip, host):
        self.conn = enip.explicit_conn(host)
        self.conn.registerSession()
        Owner.serial += 1
        self.conn.conn_serial_num += 100 * Owner.serial
        self.inp = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_INPUT, SIZE, INPUT, self.conn)
        self.out = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_OUTPUT, SIZE, OUTPUT, self.conn)
        self.producing = False

    def open(self, rpi_ms, ot_rpi_ms=None, multicast=False, rpi_unit_us=1000):
        enip_mod.config.FWD_OPEN_RPI_MULTIPLIER = rpi_unit_us
        try:
            status = self.conn.sendFwdOpenReq(INPUT, OUTPUT, CONFIG, torpi=rpi_ms,
                                              otrpi=ot_rpi_ms or rpi_ms, multiplier=2,
                                              multicast=multicast, inputsz=SIZE,
                                              outputsz=SIZE)
        finally:
            enip_mod.config.FWD_OPEN_RPI_MULTIPLIER = 1000
        if status == 0:
            self.conn.produce()
            self.producing = True
        return status

    def write(self, data):
        data = data.ljust(SIZE, b"\0")
        for i, byte in enumerate(data):
            for b in range(8):
                self.out[i * 8 + b] = bool(byte & (1 << b))

    def read(self, n=SIZE):
        bits = self.inp
        return bytes(sum(1 << b for b in range(8) if bits[i * 8 + b]) for i in range(n))

    def wait_for(self, predicate, seconds, n=32):
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            data = self.read(n)
            if data == self.read(n) and predicate(data):
                return True
            time.sleep(0.0005)
        return False

    def close(self):
        if self.producing:
            self.conn.stopProduce()
            self.producing = False
            time.sleep(0.02)
        return self.conn.sendFwdCloseReq(INPUT, OUTPUT, CONFIG)

    def done(self):
        """Ends the session and its TCP connection (the adapter serves 3 at a time)."""
        if self.producing:
            self.conn.stopProduce()
            self.producing = False
        self.conn.unregisterSession()
        self.conn.sock.close()


def dint(data, offset):
    return struct.unpack_from("<i", data, offset)[0]


def main():
    spec = json.load(sys.stdin)
    host, rpi = spec["host"], spec["rpi_ms"]
    res = {}
    enip = EtherNetIP(host)
    enip.startIO()
    try:
        scenario(enip, host, rpi, res)
    finally:
        enip.stopIO()
    print(json.dumps(res))


def scenario(enip, host, rpi, res):
    with CIPDriver(host) as d:
        res["configure"] = ipa.configure(d, FOUR_GROUPS)
        ipa.write_longs(d, 38912, [11, 12])
        ipa.write_floats(d, 39168, [1.5, 2.5])
        owner = Owner(enip, host)
        out = struct.pack("<3i2f", 9, 8, 7, 1.75, -2.0)
        owner.write(out)
        res["open"] = owner.open(rpi)
        # T->O: 2 DINTs then 2 REALs, from byte 0; zeros after 16 bytes.
        res["t_o_initial"] = owner.wait_for(
            lambda b: b[:16] == struct.pack("<2i2f", 11, 12, 1.5, 2.5), 2.0)
        res["t_o_tail_zero"] = owner.read()[16:] == bytes(SIZE - 16)
        # O->T lands in the parameters (3 DINTs to longs, 2 REALs to longs: 1, -2).
        deadline = time.monotonic() + 2.0
        while time.monotonic() < deadline:
            longs = ipa.read_longs(d, 39000, 3)
            if longs == [9, 8, 7]:
                break
            time.sleep(0.005)
        res["o_t_longs"] = ipa.read_longs(d, 39000, 3)
        res["o_t_reals_as_longs"] = ipa.read_longs(d, 39300, 2)
        # An explicit write to a produced parameter, seen in T->O: delay in ms.
        t0 = time.monotonic()
        ipa.write_longs(d, 38913, [4242])
        written = time.monotonic()
        seen = owner.wait_for(lambda b: dint(b, 4) == 4242, 2.0)
        res["write_to_t_o_ms"] = (time.monotonic() - written) * 1000.0 if seen else None
        res["write_request_ms"] = (written - t0) * 1000.0
        res["status_open"] = ipa.read_longs(d, 37424, 16)
        # A second exclusive owner from another session: refused, the first runs on.
        second = Owner(enip, host)
        res["second_open"] = second.open(rpi)
        second.done()
        ipa.write_longs(d, 38912, [-5])
        res["first_still_runs"] = owner.wait_for(lambda b: dint(b, 0) == -5, 2.0)
        res["status_after_second"] = ipa.read_longs(d, 37433, 1)
        # P37429/P37430 still describe the running connection's client.
        res["client_after_second"] = ipa.read_longs(d, 37429, 2)
        res["close"] = owner.close()
        owner.done()
        time.sleep(0.05)
        res["status_closed"] = ipa.read_longs(d, 37433, 1)

        # Configuration errors.
        errors = {
            "error2": [(4096, 1, 0, 1)] * 17,
            "error3": [(4096, 8, 0, 1), (4104, 8, 0, 1), (4112, 9, 0, 1)],
            "error4": [(38912 + 8 * g, 8, 0, 1) for g in range(13)],
            "error5": [(38912 + 8 * g, 8, 1, 2) for g in range(13)],
            "error7_example2": [(4096, 2, 0, 1), (10, 8, 0, 1), (38912, 1, 0, 1),
                                (39000, 1, 1, 1)],
        }
        for name, groups in errors.items():
            if len(groups) > 16:
                ipa.configure(d, groups[:16])
                ipa.write_longs(d, 37434, [len(groups)])
            else:
                ipa.configure(d, groups)
            o = Owner(enip, host)
            res[name] = {"open": o.open(rpi), "status": ipa.read_longs(d, 37433, 5)}
            o.done()

        # RPI limits: 0.5 ms either way refused, 1 ms accepted.
        ipa.configure(d, FOUR_GROUPS)
        o = Owner(enip, host)
        res["rpi_ot_half_ms"] = o.open(20, ot_rpi_ms=1, rpi_unit_us=500)
        res["rpi_to_half_ms"] = o.open(1, ot_rpi_ms=20, rpi_unit_us=500)
        res["rpi_1ms"] = o.open(1)
        res["status_1ms"] = ipa.read_longs(d, 37431, 3)
        o.close()
        o.done()
        # Multicast T->O.
        m = Owner(enip, host)
        res["multicast_open"] = m.open(rpi, multicast=True)
        res["multicast_status"] = ipa.read_longs(d, 37433, 1)
        m.close()
        m.done()
        time.sleep(0.05)
        # Loss of O->T without Forward_Close: the watchdog (16 x RPI) closes the connection.
        lost = Owner(enip, host)
        res["timeout_open"] = lost.open(rpi)
        time.sleep(0.1)
        lost.conn.stopProduce()
        lost.producing = False
        stopped = time.monotonic()
        deadline = stopped + 3.0
        while time.monotonic() < deadline and ipa.read_longs(d, 37433, 1) != [0]:
            time.sleep(0.005)
        res["timeout_closed_ms"] = (time.monotonic() - stopped) * 1000.0
        res["timeout_status"] = ipa.read_longs(d, 37433, 1)
        lost.done()
        again = Owner(enip, host)
        res["timeout_reopen"] = again.open(rpi)
        again.close()
        again.done()
        res["counters"] = ipa.read_longs(d, 37424, 4)


if __name__ == "__main__":
    main()
