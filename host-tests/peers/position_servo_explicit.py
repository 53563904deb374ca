"""Explicit messages to the PositionServo profile with pycomm3 (UCMM): manual example 6.3
(Get/Set_Attribute_Single of class 0x64 instance 100 attribute 2, then attribute 0), the
string and EPM attributes, the CIP statuses of bad requests, the class attributes and the
attribute lists, Get_Attributes_All of an assembly (7.3), the Identity object (7.1), and
the multicast TTL/address being one setting in variables 273/275 and TCP/IP attributes 8/9.
An Identity Reset (type 0) in the middle shows the EPM copy coming back into RAM; a board that
really restarts drops the connection, so the script reconnects after it.

Reads {"host"} on stdin. Prints one JSON line of named results: each a general status
and/or the reply data in hex.
"""
import json
import struct
import sys
import time

from pycomm3 import CIPDriver

import position_servo_common as ps
from explicit_request import raw


def var(driver, service, instance, attribute, data=b""):
    return raw(driver, service, ps.SYSTEM940, instance, attribute, data)


def text(s):
    return struct.pack("<I", len(s)) + s.encode()


def reconnect(host, old):
    """A new driver once the board answers again (a board that really restarts on an
    Identity Reset drops the connection); bounded."""
    try:
        old.close()
    except Exception:  # the board may have reset the connection already
        pass
    for _ in range(40):
        time.sleep(0.25)
        driver = CIPDriver(host)
        try:
            driver.open()
            return driver
        except Exception:  # not up yet
            continue
    raise RuntimeError("the board did not come back after the Identity Reset")


def main():
    host = json.load(sys.stdin)["host"]
    r = {}
    get, put = ps.GET, ps.SET
    d = CIPDriver(host)
    d.open()
    try:
        # Example 6.3: V0 as REAL, written as REAL, read as integer.
        r["v0_real_before"] = var(d, get, 100, 2)
        r["v0_set_real"] = var(d, put, 100, 2, struct.pack("<f", 1234.5))
        r["v0_real"] = var(d, get, 100, 2)
        r["v0_int"] = var(d, get, 100, 0)
        r["v0_text"] = var(d, get, 100, 4)
        r["v0_epm_reads_ram"] = var(d, get, 100, 3)
        r["v1_set_text"] = var(d, put, 101, 4, text("-2.25"))
        r["v1_real"] = var(d, get, 101, 2)
        # EPM: V2 written to the EPM, then V2's RAM copy changed; Reset (power cycle)
        # restores the EPM value.
        r["v2_set_epm"] = var(d, put, 102, 3, struct.pack("<f", 7.0))
        r["v2_set_ram"] = var(d, put, 102, 2, struct.pack("<f", 8.0))
        r["v2_before_reset"] = var(d, get, 102, 2)
        r["identity_reset"] = raw(d, 0x05, 0x01, 1, None, b"\x00")
        d = reconnect(host, d)
        r["v2_after_reset"] = var(d, get, 102, 2)
        # Statuses.
        r["unknown_variable"] = var(d, get, 99, 0)
        r["unknown_attribute"] = var(d, get, 100, 6)
        r["read_only"] = var(d, put, 215, 2, struct.pack("<f", 1.0))
        r["no_epm_copy"] = var(d, put, 52, 1, struct.pack("<I", 1))
        r["out_of_range"] = var(d, put, 34, 0, struct.pack("<I", 9))
        r["short_data"] = var(d, put, 100, 2, b"\x00\x00")
        r["bad_text"] = var(d, put, 100, 4, text("fast"))
        # The class and the attribute lists, served by the stack like any CIP object:
        # class attributes 1 (revision) and 2 (highest instance); V0 set to 12 as integer
        # and then 12.5 as REAL in one Set_Attribute_List, read back as both in one
        # Get_Attribute_List.
        r["class_revision"] = var(d, get, 0, 1)
        r["class_max_instance"] = var(d, get, 0, 2)
        r["list_set"] = var(d, 0x04, 100, None, struct.pack("<HHiHf", 2, 0, 12, 2, 12.5))
        r["list_get"] = var(d, 0x03, 100, None, struct.pack("<HHH", 2, 0, 2))
        # 7.3: the assembly instances answer Get_Attributes_All with their data.
        r["assembly_106_data"] = raw(d, get, 0x04, 106, 3)
        r["assembly_106_all"] = raw(d, 0x01, 0x04, 106, None)
        # Identity.
        r["product_name"] = raw(d, get, 0x01, 1, 7)
        r["identity_all"] = raw(d, 0x01, 0x01, 1, None)
        # Multicast: defaults, then the variables and the TCP/IP attributes agree.
        r["ttl_default"] = raw(d, get, 0xF5, 1, 8)
        r["mcast_default"] = raw(d, get, 0xF5, 1, 9)
        r["var_275_default"] = var(d, get, 275, 0)
        r["set_var_273"] = var(d, put, 273, 0, struct.pack("<I", 5))
        r["set_var_275"] = var(d, put, 275, 0, struct.pack("<I", 0xEFC00203))
        r["ttl_after_vars"] = raw(d, get, 0xF5, 1, 8)
        r["mcast_after_vars"] = raw(d, get, 0xF5, 1, 9)
        r["set_attr_8"] = raw(d, put, 0xF5, 1, 8, b"\x07")
        r["set_attr_9"] = raw(d, put, 0xF5, 1, 9, bytes([1, 0, 1, 0, 9, 9, 192, 239]))
        r["set_attr_9_two"] = raw(d, put, 0xF5, 1, 9, bytes([1, 0, 2, 0, 9, 9, 192, 239]))
        r["var_273_after_attr"] = var(d, get, 273, 0)
        r["var_275_after_attr"] = var(d, get, 275, 0)
    finally:
        d.close()
    print(json.dumps(r))


if __name__ == "__main__":
    main()
