"""Electronic keys in explicit request paths, sent by pycomm3's CIPDriver.generic_message.

pycomm3 builds a request path from class, instance and attribute only; this script puts a
key segment (0x34, format 4) in front of that path (the one piece it adds: pycomm3 frames,
wraps in Unconnected_Send, opens the Class 3 connection, sends and parses the replies).

Reads one JSON document from stdin:
  {"host": "198.18.0.2",
   "requests": [{"name": str, "via": "ucmm" | "ucs" | "class3", "key": hex str | null,
                 "service": int, "class": int, "instance": int, "attribute": int | null,
                 "data": hex str}],
   "multiple": [{"name": str, "members": [{"key": hex str | null, "service": int,
                 "class": int, "instance": int, "attribute": int | null}]}]}
"requests" go one by one the way "via" says (UCMM, Unconnected_Send with route 1/0,
Class 3); each "multiple" is one UCMM Multiple_Service_Packet (0x0A to the Message Router)
whose members carry their own keys.
Prints one JSON line:
  {"results": [{"name", "status", "extended": [int], "data": hex, "error"}],
   "multiple": [{"name", "status", "members": [{"status", "extended": [int], "data": hex}]}]}
"""
import json
import struct
import sys

import pycomm3.packets.cip as cip_packets
from pycomm3 import CIPDriver
from pycomm3.packets.util import request_path as plain_request_path

# Where the Message Router response's general status sits in pycomm3's raw reply:
# SendRRData (unconnected) and SendUnitData (connected).
GENERAL_AT = {False: 42, True: 48}


def keyed_request_path(key):
    """pycomm3's request path builder with the key segment `key` in front."""
    def build(class_code, instance, attribute=b""):
        path = plain_request_path(class_code, instance, attribute)
        # path[0] is the path size in words; the key is 10 bytes, 5 words.
        return bytes([path[0] + len(key) // 2]) + key + path[1:]
    return build


def status_words(raw, at):
    """General status, additional status words and the data after them, from `raw`."""
    general = raw[at]
    size = raw[at + 1]
    words = [w for (w,) in struct.iter_unpack("<H", raw[at + 2:at + 2 + 2 * size])]
    return general, words, raw[at + 2 + 2 * size:]


def attribute_bytes(attribute):
    # pycomm3 drops an integer attribute 0, so attribute ids travel as bytes.
    return b"" if attribute is None else bytes([attribute])


def run(driver, req):
    key = bytes.fromhex(req["key"]) if req.get("key") else None
    via = req["via"]
    connected = via == "class3"
    cip_packets.request_path = keyed_request_path(key) if key else plain_request_path
    try:
        tag = driver.generic_message(
            service=req["service"],
            class_code=req["class"],
            instance=req["instance"],
            attribute=attribute_bytes(req.get("attribute")),
            request_data=bytes.fromhex(req.get("data", "")),
            name=req["name"],
            connected=connected,
            unconnected_send=via == "ucs",
            route_path="1/0" if via == "ucs" else False,
            return_response_packet=True,
        )
    finally:
        cip_packets.request_path = plain_request_path
    response = tag.value
    out = {"name": req["name"], "status": None, "extended": [], "data": "",
           "error": tag.error}
    if response is not None and getattr(response, "raw", None):
        general, words, data = status_words(response.raw, GENERAL_AT[connected])
        out.update(status=response.service_status, general_raw=general, extended=words,
                   data=data.hex())
    return out


def member_bytes(m):
    path = plain_request_path(m["class"], m["instance"], attribute_bytes(m.get("attribute")))
    if m.get("key"):
        key = bytes.fromhex(m["key"])
        path = bytes([path[0] + len(key) // 2]) + key + path[1:]
    return bytes([m["service"]]) + path + bytes.fromhex(m.get("data", ""))


def multiple(driver, spec):
    members = [member_bytes(m) for m in spec["members"]]
    body = struct.pack("<H", len(members))
    offset = 2 + 2 * len(members)
    for m in members:
        body += struct.pack("<H", offset)
        offset += len(m)
    body += b"".join(members)
    tag = driver.generic_message(service=0x0A, class_code=0x02, instance=1,
                                 request_data=body, name=spec["name"], connected=False,
                                 unconnected_send=False, route_path=False,
                                 return_response_packet=True)
    response = tag.value
    out = {"name": spec["name"], "status": None, "members": [], "error": tag.error}
    if response is None or not getattr(response, "raw", None):
        return out
    general, _, reply = status_words(response.raw, GENERAL_AT[False])
    out["status"] = general
    count = struct.unpack_from("<H", reply, 0)[0]
    offsets = [struct.unpack_from("<H", reply, 2 + 2 * i)[0] for i in range(count)]
    ends = offsets[1:] + [len(reply)]
    for start, end in zip(offsets, ends):
        # Each member reply: service | 0x80, reserved, general status, size, words, data.
        g, words, data = status_words(reply[start:end], 2)
        out["members"].append({"status": g, "extended": words, "data": data.hex()})
    return out


def main():
    spec = json.load(sys.stdin)
    with CIPDriver(spec["host"]) as driver:
        results = [run(driver, r) for r in spec.get("requests", [])]
        multiples = [multiple(driver, m) for m in spec.get("multiple", [])]
    print(json.dumps({"results": results, "multiple": multiples}))


if __name__ == "__main__":
    main()
