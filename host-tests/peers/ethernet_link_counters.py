"""Ethernet Link counters (class 0xF6, attributes 4 and 5) read with pycomm3 around known
traffic this script sends itself.

Reads one JSON document from stdin:
  {"host": "198.18.0.2", "broadcast": "198.18.0.255", "iface": "enip0",
   "unicast": N, "nucast": M, "unknown": K}
Then, in one pycomm3 session: reads attribute 3 (MAC) and 4 ("before"); sends N unicast
ListIdentity requests over UDP and waits for each reply, M broadcast UDP datagrams to the
discard port, and K raw frames of the local experimental EtherType 0x88B5 to the board's MAC;
reads attribute 4 ("after"), Get_And_Clear (0x4C) of attribute 4 ("cleared"), attribute 4
again ("after_clear") and attribute 5 ("media").
Prints one JSON line with the MAC and each reading in hex, and how many ListIdentity
replies came back.
"""
import json
import socket
import struct
import sys

from pycomm3 import CIPDriver

LIST_IDENTITY = struct.pack("<HHII8sI", 0x63, 0, 0, 0, b"\0" * 8, 0)


def attribute(driver, service, attr):
    tag = driver.generic_message(
        service=service,
        class_code=0xF6,
        instance=1,
        attribute=bytes([attr]),
        request_data=b"",
        connected=False,
        unconnected_send=False,
        route_path=False,
        name=f"f6.{attr}",
        return_response_packet=True,
    )
    if tag.error:
        raise RuntimeError(f"service {service:#x} attribute {attr}: {tag.error}")
    return tag.value.value.hex()


def send_traffic(spec, mac):
    replies = 0
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.settimeout(1.0)
        for _ in range(spec["unicast"]):
            s.sendto(LIST_IDENTITY, (spec["host"], 44818))
            try:
                s.recvfrom(2048)
                replies += 1
            except socket.timeout:
                pass
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
        for _ in range(spec["nucast"]):
            s.sendto(b"\0" * 18, (spec["broadcast"], 9))
    with socket.socket(socket.AF_PACKET, socket.SOCK_RAW) as s:
        s.bind((spec["iface"], 0))
        src = s.getsockname()[4]
        for _ in range(spec["unknown"]):
            s.send(mac + src + b"\x88\xb5" + b"\0" * 46)
    return replies


def main():
    spec = json.load(sys.stdin)
    out = {}
    with CIPDriver(spec["host"]) as driver:
        mac = bytes.fromhex(attribute(driver, 0x0E, 3))
        out["mac"] = mac.hex()
        out["before"] = attribute(driver, 0x0E, 4)
        out["replies"] = send_traffic(spec, mac)
        out["after"] = attribute(driver, 0x0E, 4)
        out["cleared"] = attribute(driver, 0x4C, 4)
        out["after_clear"] = attribute(driver, 0x0E, 4)
        out["media"] = attribute(driver, 0x0E, 5)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
