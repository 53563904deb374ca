"""The embedded board's diagnostics object (vendor class 0x3A0, instance 1) read with
pycomm3, after the board's identity (ListIdentity) answers.

Reads one JSON document from stdin: {"host": "198.18.0.2", "wait": SECONDS}.
Waits (bounded by "wait") until a pycomm3 ListIdentity of the host answers, then reads
attributes 1 (stack region bytes), 2 (bytes painted at boot) and 3 (high-water mark) with
Get_Attribute_Single. Prints one JSON line: {"product_name": ..., "size": N, "painted": N,
"deepest": N, "waited": SECONDS}.
"""
import json
import struct
import sys
import time

from pycomm3 import CIPDriver

CLASS = 0x3A0


def attribute(driver, attr):
    tag = driver.generic_message(service=0x0E, class_code=CLASS, instance=1,
                                 attribute=bytes([attr]), connected=False,
                                 unconnected_send=False, route_path=False,
                                 name=f"diag.{attr}")
    if tag.error:
        raise RuntimeError(f"attribute {attr}: {tag.error}")
    return struct.unpack("<I", tag.value[:4])[0]


def main():
    spec = json.load(sys.stdin)
    start = time.monotonic()
    identity = None
    while identity is None:
        try:
            identity = CIPDriver.list_identity(spec["host"])
        except Exception:  # noqa: BLE001 - a board still booting answers nothing
            identity = None
        if identity is None:
            if time.monotonic() - start > spec["wait"]:
                sys.exit(f"no ListIdentity answer from {spec['host']} in {spec['wait']} s")
            time.sleep(0.25)
    waited = time.monotonic() - start
    with CIPDriver(spec["host"]) as driver:
        out = {
            "product_name": identity.get("product_name"),
            "size": attribute(driver, 1),
            "painted": attribute(driver, 2),
            "deepest": attribute(driver, 3),
            "waited": round(waited, 2),
        }
    print(json.dumps(out))


main()
