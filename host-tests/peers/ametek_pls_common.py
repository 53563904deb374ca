"""Helpers shared by the ametek_pls_* peers: the 7500 PLS classes 0xC0/0xC1 through pycomm3
explicit messages (CIP Generic, instance 1, as the manual's §3.2 MSG instruction), and the
Class 1 connection of the manual's §3.1 (input 100, 17 INT words; output 150, 7 INT words;
configuration 1, no data) through the PyPI `ethernetip` package.

Not a peer itself: the scenario scripts import it (their directory is on sys.path).
"""
import struct
import time

from ethernetip.ethernetip import EtherNetIP

import explicit_request
import position_servo_common as ps

STATUS, CONFIG = 0xC0, 0xC1
GET, SET = 0x0E, 0x10
INPUT, OUTPUT, CONFIG_ASSEMBLY = 100, 150, 1
RUN, ADDON, ACK = 1, 2, 4


def request(driver, service, cls, attribute, data=b""):
    """One UCMM request to instance 1; returns (general status or None, reply bytes)."""
    return explicit_request.request(driver, service, cls, 1, attribute, data)


def le(words):
    return b"".join(struct.pack("<H", w & 0xFFFF) for w in words)


def words(data):
    return list(struct.unpack("<" + "H" * (len(data) // 2), data[: len(data) // 2 * 2]))


def set_words(driver, attribute, w):
    return request(driver, SET, CONFIG, attribute, le(w))[0]


def get_words(driver, cls, attribute):
    status, data = request(driver, GET, cls, attribute)
    return words(data) if status == 0 else None


def pls_object():
    """§2.3 example of the digest (4.1): group 1 SF 360 with output 1, output 17, input 9."""
    w = [0] * 48
    for g in range(8):
        w[6 * g] = 360
    w[1], w[2], w[3] = 0x0001, 0x0001, 0x0100
    return w


def output_1():
    """Output 1: no compensation, 2 standard setpoints 100-200 and 300-330."""
    w = [0] * 26
    w[6], w[7], w[8], w[9], w[12], w[13] = 2, 1, 100, 200, 300, 330
    return w


def output_17():
    """Output 17: 1 standard setpoint 50-60."""
    w = [0] * 20
    w[0], w[1], w[2], w[3] = 1, 1, 50, 60
    return w


def home(driver, position, group=0):
    """Home offset: group `group` (0-based) position becomes `position`."""
    w = [0] * 9
    w[0] = 1 << (2 * group)
    w[group + 1] = position
    return set_words(driver, 36, w)


def write_program(driver):
    """The test program (the PLS object, outputs 1 and 17); the three Set statuses."""
    return [set_words(driver, 1, pls_object()),
            set_words(driver, 2, output_1()),
            set_words(driver, 18, output_17())]


def start_owner(ip, rpi_ms, multiplier):
    """The `ethernetip` I/O started and an exclusive owner on it, its time 0 now:
    (the EtherNetIP object to stop, the owner)."""
    enip = EtherNetIP(ip)
    enip.startIO()
    return enip, Owner(enip, ip, rpi_ms, multiplier, time.monotonic())


class Owner(ps.Class1):
    """The exclusive owner 150/100 with the empty configuration assembly 1."""

    def __init__(self, enip, ip, rpi_ms, multiplier, t0):
        super().__init__(enip, ip, INPUT, 34, OUTPUT, 14, rpi_ms, multiplier, t0)
        self.points = (INPUT, OUTPUT, CONFIG_ASSEMBLY)

    def send(self, w):
        self.write(le(w + [0] * (7 - len(w))))

    def words(self):
        return words(self.read())

    def wait_words(self, predicate, seconds):
        return self.wait_for(lambda d: predicate(words(d)), seconds)

    def run(self, rpi_ms):
        """Run mode, Forward_Open, then the first data settled; the Forward_Open's status."""
        self.send([RUN])
        status = self.open()
        self.settle(rpi_ms)
        return status

    def settle(self, rpi_ms):
        """Lets output data written now reach the board and come back in the input data."""
        time.sleep(0.02 + 6 * rpi_ms / 1000.0)
