"""Demo, first part: pycomm3 prints the board's Identity object (class 0x01, instance 1).

Usage: python demo_identity.py BOARD_IP. Waits (bounded) for the board to listen first.
"""
import socket
import struct
import sys
import time

from pycomm3 import CIPDriver, Services

ip = sys.argv[1]
deadline = time.monotonic() + 15
while True:  # bounded: wait at most 15 s for the board to listen
    try:
        socket.create_connection((ip, 44818), timeout=0.5).close()
        break
    except OSError:
        if time.monotonic() > deadline:
            sys.exit(f"the board at {ip}:44818 did not come up")
        time.sleep(0.25)


def get(driver, attribute):
    # Attribute ids as bytes: pycomm3 drops an integer attribute 0 otherwise.
    reply = driver.generic_message(service=Services.get_attribute_single, class_code=0x01,
                                   instance=1, attribute=bytes([attribute]), connected=False,
                                   unconnected_send=False, route_path=False)
    if reply.error:
        sys.exit(f"Get_Attribute_Single 0x01/1/{attribute} failed: {reply.error}")
    return reply.value


u16 = lambda b: struct.unpack("<H", b[:2])[0]
rows = [
    ("Vendor ID", lambda b: f"{u16(b)}"),
    ("Device type", lambda b: f"{u16(b):#06x}"),
    ("Product code", lambda b: f"{u16(b)}"),
    ("Revision", lambda b: f"{b[0]}.{b[1]:03d}"),
    ("Status", lambda b: f"{u16(b):#06x}"),
    ("Serial number", lambda b: f"{struct.unpack('<I', b[:4])[0]:#010x}"),
    ("Product name", lambda b: b[1:1 + b[0]].decode("ascii", "replace")),
]
with CIPDriver(ip) as driver:
    print(f"Identity of {ip} (pycomm3, class 0x01 instance 1):")
    for attribute, (name, show) in enumerate(rows, start=1):
        print(f"  {attribute}  {name:<14} {show(get(driver, attribute))}")
