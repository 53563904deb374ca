"""Class 3 connected explicit messaging with pycomm3: generic_message(connected=True) opens
a Forward_Open (Large first, then the 500-byte form) and sends SendUnitData.

Reads {"host": str} as JSON from stdin. Reads Identity attribute 7, writes 32 bytes to
assembly 154 and reads them back. Prints one JSON line:
{"name": hex, "set_error": str|null, "get": hex, "connection_size": int}.
"""
import json
import sys

from pycomm3 import CIPDriver, Services

req = json.load(sys.stdin)
out = {}
with CIPDriver(req["host"]) as d:
    def msg(service, cls, inst, attr, data=b"", name="m"):
        # Attribute ids as bytes: pycomm3 drops an integer attribute 0 otherwise.
        return d.generic_message(service=service, class_code=cls, instance=inst, attribute=bytes([attr]),
                                 request_data=data, connected=True, unconnected_send=False,
                                 route_path=False, name=name)
    r = msg(Services.get_attribute_single, 1, 1, 7)
    out["name"] = r.value.hex() if r.value else None
    out["name_error"] = r.error
    r = msg(Services.set_attribute_single, 4, 154, 3, bytes(range(100, 132)))
    out["set_error"] = r.error
    r = msg(Services.get_attribute_single, 4, 154, 3)
    out["get"] = r.value.hex() if r.value else None
    out["connection_size"] = d.connection_size
print(json.dumps(out))
