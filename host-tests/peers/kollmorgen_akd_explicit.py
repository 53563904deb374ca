"""Explicit messages to the AKD profile with pycomm3 (UCMM): the Position Controller object
(0x25, with attribute 22), the Position Controller Supervisor (0x24) and the Parameter
object (0x0F) read and written, with the statuses the manual gives (p.10): not settable
0x0E, attribute not supported 0x14, service not supported 0x08, class not supported 0x16,
value out of range 0x09; the parameter lengths (p.26); the drive's own ranges and defaults
(SWLS.EN 0-3, MT.NUM 0-128, MT.CNTL 3, MT.SET of a task with MT.V 0); the
Identity's vendor ID.

Reads {"host"} on stdin. Prints one JSON line of named results (status and reply hex).
"""
import json
import struct
import sys

from pycomm3 import CIPDriver

import kollmorgen_akd_common as akd

PC, PAR, GET, SET = akd.POSITION_CONTROLLER, akd.PARAMETER, akd.GET, akd.SET


def main():
    host = json.load(sys.stdin)["host"]
    r = {}
    d = CIPDriver(host)
    d.open()
    try:
        pc = lambda service, a, data=b"": akd.raw(d, service, PC, 1, a, data)
        par = lambda service, i, a, data=b"": akd.raw(d, service, PAR, i, a, data)
        r["count"] = pc(GET, 1)
        r["list"] = pc(GET, 2)
        r["mode"] = pc(GET, 3)
        r["position_units"] = pc(GET, 4)
        r["profile_units"] = pc(GET, 5)
        r["set_target_position"] = pc(SET, 6, struct.pack("<i", -1234))
        r["target_position"] = pc(GET, 6)
        r["set_mode_velocity"] = pc(SET, 3, b"\x01")
        r["mode_after"] = pc(GET, 3)
        r["set_profunit_param"] = par(SET, 797, 1, struct.pack("<I", 1000))
        r["profile_units_after"] = pc(GET, 5)
        r["set_accel_attr"] = pc(SET, 8, struct.pack("<i", 5000))
        r["drv_acc_param"] = par(GET, 1004, 1)
        r["enable"] = pc(GET, 17)
        # Statuses.
        r["read_only"] = pc(SET, 1, b"\x05")
        r["unknown_attribute"] = pc(GET, 200)
        r["mode_out_of_range"] = pc(SET, 3, b"\x03")
        r["get_all"] = akd.raw(d, 0x01, PC, 1, None)
        r["home_move_get"] = pc(GET, 101)
        # The Position Controller Supervisor (0x24), listed by the manual (p.9).
        r["supervisor_count"] = akd.raw(d, GET, 0x24, 1, 1)
        r["supervisor_list"] = akd.raw(d, GET, 0x24, 1, 2)
        r["supervisor_axis"] = akd.raw(d, GET, 0x24, 1, 3)
        r["supervisor_set"] = akd.raw(d, SET, 0x24, 1, 6, b"\x01")
        r["absent_class"] = akd.raw(d, GET, 0x66, 1, 1)
        # Attribute 22, jog velocity (section 7).
        r["jog_velocity"] = pc(GET, 22)
        r["set_jog_velocity"] = pc(SET, 22, struct.pack("<i", -2000))
        r["jog_velocity_after"] = pc(GET, 22)
        r["vendor"] = akd.raw(d, GET, 0x01, 1, 1)
        # The drive's own ranges and defaults.
        r["swls_en_3"] = par(SET, 1022, 1, b"\x03")
        r["swls_en_4"] = par(SET, 1022, 1, b"\x04")
        r["swls_en_after"] = par(GET, 1022, 1)
        r["mt_num_128"] = par(SET, 1030, 1, bytes([128]))
        r["mt_num_129"] = par(SET, 1030, 1, bytes([129]))
        # A task that cannot move (MT.V 0, as at power-up): MT.SET refused.
        r["mt_v_zero"] = par(SET, 1033, 1, struct.pack("<q", 0))
        r["mt_set_empty"] = par(SET, 1040, 1, b"\x01")
        r["mt_cntl_3"] = par(SET, 1039, 1, struct.pack("<I", 3))
        r["mt_cntl_2"] = par(SET, 1039, 1, struct.pack("<I", 2))
        r["absent_class_2"] = akd.raw(d, GET, 0x70, 1, 1)
        # Parameters: type, length, value; a 64-bit parameter and its low word.
        r["p1_type"] = par(GET, 1, 5)
        r["p1_length"] = par(GET, 1, 6)
        r["p1_value"] = par(GET, 1, 1)
        r["p205_length"] = par(GET, 205, 6)
        r["p5_length"] = par(GET, 5, 6)
        r["p5_set32"] = par(SET, 5, 1, struct.pack("<i", -9))
        r["p5_value"] = par(GET, 5, 1)
        r["p6_value"] = par(GET, 6, 1)
        r["p1_short"] = par(SET, 1, 1, b"\x01\x02")
        r["p1_long"] = par(SET, 1, 1, b"\x01\x02\x03\x04\x05")
        r["p7_read_only"] = par(SET, 7, 1, b"\x00\x00\x00\x00")
        r["posunit_zero"] = par(SET, 796, 1, b"\x00\x00\x00\x00")
        r["unknown_parameter"] = par(GET, 12, 1)
        # HOME.MOVE while disabled: device state conflict.
        r["home_move_disabled"] = par(SET, 205, 1, b"\x01")
        # Enable through attribute 17, home through parameter 205, read the status back.
        r["set_enable"] = pc(SET, 17, b"\x01")
        r["home_move"] = par(SET, 205, 1, b"\x01")
        import time
        time.sleep(0.2)
        r["motionstat"] = par(GET, 1010, 1)
        r["set_disable"] = pc(SET, 17, b"\x00")
        r["enable_after"] = pc(GET, 17)
    finally:
        d.close()
    print(json.dumps(r))


if __name__ == "__main__":
    main()
