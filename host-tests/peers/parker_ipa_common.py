"""Helpers shared by the parker_ipa_* peers: requests to the IPA's vendor classes 0x64 (ACR
Parameter) and 0x65 (ACR Group) with pycomm3's generic_message, UCMM or Class 3.

Not a peer itself: the scenario scripts import it (their directory is on sys.path).
"""
import struct

import explicit_request

PARAMETER, GROUP = 0x64, 0x65
WRITE_FLOATS, READ_FLOATS, WRITE_LONGS, READ_LONGS, AND_OR = 0x50, 0x51, 0x52, 0x53, 0x54
WRITE_BINARY = 0x34


def request(driver, service, cls, instance, data=b"", connected=False, attribute=1):
    """One request, attribute 1 as the manual says; returns (general status, reply bytes)."""
    return explicit_request.request(driver, service, cls, instance, attribute, data, connected)


def result(status_data):
    status, data = status_data
    return {"status": status, "data": data.hex()}


def longs(values):
    return struct.pack("<%di" % len(values), *values)


def floats(values):
    return struct.pack("<%df" % len(values), *values)


def read_longs(driver, p, n, connected=False):
    status, data = request(driver, READ_LONGS, PARAMETER, p, longs([n]), connected)
    return list(struct.unpack("<%di" % (len(data) // 4), data)) if status == 0 else None


def read_floats(driver, p, n, connected=False):
    status, data = request(driver, READ_FLOATS, PARAMETER, p, longs([n]), connected)
    return list(struct.unpack("<%df" % (len(data) // 4), data)) if status == 0 else None


def write_longs(driver, p, values, connected=False):
    return request(driver, WRITE_LONGS, PARAMETER, p, longs(values), connected)[0]


def write_floats(driver, p, values, connected=False):
    return request(driver, WRITE_FLOATS, PARAMETER, p, floats(values), connected)[0]


def configure(driver, groups):
    """P37434 = len(groups), then each group's four longs from P37440."""
    status = write_longs(driver, 37434, [len(groups)])
    for g, entry in enumerate(groups):
        status = status or write_longs(driver, 37440 + 4 * g, list(entry))
    return status
