"""Shared by smoke_explicit.py and demo_identity.py (not a peer itself): wait for the board
to listen, and read its Identity object (class 0x01, instance 1, attributes 1-7) with
pycomm3."""
import socket
import struct
import sys
import time

from pycomm3 import CIPDriver, Services


def wait_for_board(ip, seconds=15):
    """Returns once `ip` accepts TCP on 44818; exits after `seconds` (bounded)."""
    deadline = time.monotonic() + seconds
    while True:
        try:
            socket.create_connection((ip, 44818), timeout=0.5).close()
            return
        except OSError:
            if time.monotonic() > deadline:
                sys.exit(f"the board at {ip}:44818 did not come up")
            time.sleep(0.25)


def u16(b):
    return struct.unpack("<H", b[:2])[0]


# attribute, JSON key, label, formatting of the raw reply data
IDENTITY = [
    (1, "vendor_id", "Vendor ID", lambda b: f"{u16(b)}"),
    (2, "device_type", "Device type", lambda b: f"{u16(b):#06x}"),
    (3, "product_code", "Product code", lambda b: f"{u16(b)}"),
    (4, "revision", "Revision", lambda b: f"{b[0]}.{b[1]:03d}"),
    (5, "status", "Status", lambda b: f"{u16(b):#06x}"),
    (6, "serial_number", "Serial number", lambda b: f"{struct.unpack('<I', b[:4])[0]:#010x}"),
    (7, "product_name", "Product name", lambda b: b[1:1 + b[0]].decode("ascii", "replace")),
]


def read_identity(driver):
    """[(attribute, key, label, text)] for Identity attributes 1-7; exits on an error."""
    rows = []
    for attribute, key, label, show in IDENTITY:
        # Attribute ids as bytes: pycomm3 drops an integer attribute 0 otherwise.
        reply = driver.generic_message(service=Services.get_attribute_single, class_code=0x01,
                                       instance=1, attribute=bytes([attribute]), connected=False,
                                       unconnected_send=False, route_path=False)
        if reply.error:
            sys.exit(f"Identity attribute {attribute}: {reply.error}")
        rows.append((attribute, key, label, show(reply.value)))
    return rows
