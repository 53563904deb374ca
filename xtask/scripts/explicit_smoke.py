"""QEMU smoke run, explicit part: pycomm3 reads the Identity object of the board and
discovers it with a ListIdentity broadcast to the subnet.

Usage: python explicit_smoke.py BOARD_IP BROADCAST. Waits (bounded) for the board to
accept TCP on 44818. Prints one JSON line:
{"identity": {attribute name: value}, "discovered": [{"ip_address", "product_name"}]}.
"""
import json
import socket
import struct
import sys
import time

from pycomm3 import CIPDriver, Services
from pycomm3.packets import ListIdentityRequestPacket

ip, broadcast = sys.argv[1], sys.argv[2]
deadline = time.monotonic() + 15
while True:  # bounded: at most 15 s
    try:
        socket.create_connection((ip, 44818), timeout=0.5).close()
        break
    except OSError:
        if time.monotonic() > deadline:
            sys.exit(f"{ip}:44818 does not accept connections")
        time.sleep(0.25)


def get(driver, attribute):
    # Attribute ids as bytes: pycomm3 drops an integer attribute 0 otherwise.
    reply = driver.generic_message(service=Services.get_attribute_single, class_code=0x01,
                                   instance=1, attribute=bytes([attribute]), connected=False,
                                   unconnected_send=False, route_path=False)
    if reply.error:
        sys.exit(f"Identity attribute {attribute}: {reply.error}")
    return reply.value


u16 = lambda b: struct.unpack("<H", b[:2])[0]
with CIPDriver(ip) as driver:
    identity = {
        "vendor_id": u16(get(driver, 1)),
        "device_type": u16(get(driver, 2)),
        "product_code": u16(get(driver, 3)),
        "revision": "%d.%03d" % tuple(get(driver, 4)[:2]),
        "status": "%#06x" % u16(get(driver, 5)),
        "serial_number": "%#010x" % struct.unpack("<I", get(driver, 6)[:4])[0],
        "product_name": (lambda b: b[1:1 + b[0]].decode("ascii", "replace"))(get(driver, 7)),
    }
# pycomm3's own discover() sends an all-zero sender context, whose first two bytes ask for
# the default maximum reply delay of 2 s, but listens for only 1 s. So build its ListIdentity
# with a 500 ms maximum and broadcast it with its own helper (up to 3 tries, bounded).
request = ListIdentityRequestPacket()
context = struct.pack("<H", 500) + bytes(6)
message = request.build_request(None, CIPDriver("0.0.0.0")._session, context, 0)
found = []
for _ in range(3):
    found = CIPDriver._broadcast_discover(None, message, request, broadcast)
    if found:
        break
discovered = [{"ip_address": d.get("ip_address"), "product_name": d.get("product_name")}
              for d in found]
print(json.dumps({"identity": identity, "discovered": discovered}))
