"""QEMU smoke run (host-tests/tests/qemu_smoke.rs), explicit part: pycomm3 reads the
Identity object of the board and discovers it with a ListIdentity broadcast to the subnet.

Usage: python smoke_explicit.py BOARD_IP BROADCAST. Prints one JSON line:
{"identity": {key: text}, "discovered": [{"ip_address", "product_name"}]}.
"""
import json
import struct
import sys

from pycomm3 import CIPDriver
from pycomm3.packets import ListIdentityRequestPacket

from identity import read_identity, wait_for_board

ip, broadcast = sys.argv[1], sys.argv[2]
wait_for_board(ip)
with CIPDriver(ip) as driver:
    identity = {key: text for _, key, _, text in read_identity(driver)}
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
