"""The AKD's Class 1 behaviour with the PyPI `ethernetip` package as exclusive owner of
command 101 / response 102 (configuration 100) at the manual's minimum RPI (10 ms), and
pycomm3 for the explicit side: the handshake example, Load/Start edges, the error
response, jog and stops in velocity mode, the not-homed fault (a move and a jog), homing
through HOME.MOVE (parameter 205) and an absolute move in position mode, DRV.MOTIONSTAT bits
10/11/14/15, a motion task run by Start Block and followed through a refused load,
Attribute to Get, a zero target velocity, the torque response within the peak current, a
refused map-type-2 load that changes nothing; then the admission rules (5 ms refused,
multicast accepted).

Reads {"host", "rpi_ms", "multiplier"} on stdin. Prints one JSON line of named results
(responses in hex, times in ms).
"""
import json
import struct
import sys
import time

from pycomm3 import CIPDriver
from ethernetip.ethernetip import EtherNetIP

import kollmorgen_akd_common as akd
from kollmorgen_akd_common import (ENABLE, LOAD, DIRECTION, SMOOTH_STOP, HARD_STOP, RELATIVE,
                                   START_BLOCK, BLOCK,
                                   ENABLED, HOMED, CUR_DIR, FAULT, IN_POSITION, IN_MOTION,
                                   LOAD_COMPLETE, command, dint)

JOG = dict(ctype=0x27, rtype=0x23, velocity=1000, accel=10000, decel=10000)


def mode(d, m):
    return akd.raw(d, akd.SET, akd.POSITION_CONTROLLER, 1, 3, bytes([m]))["status"]


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult = req["host"], req["rpi_ms"], req["multiplier"]
    out = {}
    d = CIPDriver(ip)
    d.open()
    enip = EtherNetIP(ip)
    enip.startIO()
    owner = akd.Owner(enip, ip, rpi, mult)
    try:
        # The handshake example [HS]: Enable, target position 1000, Load/Start 0.
        owner.send(command(ENABLE, 0x21, 0x20, 1000))
        out["forward_open"] = owner.open()
        time.sleep(0.1)
        r = owner.read()
        out["first_response"] = r.hex()
        # MT.TPOSWND at power-up: 0.5 rev (32768 units).
        out["tposwnd_default"] = akd.raw(d, akd.GET, akd.PARAMETER, 1015, 1)
        # Position mode before homing: a move faults the drive.
        owner.exchange(command(ENABLE, 0x26, 0x20, position=100, velocity=1000,
                               accel=10000, decel=10000))
        r = owner.exchange(command(ENABLE | LOAD, 0x26, 0x20, position=100, velocity=1000,
                                   accel=10000, decel=10000))
        out["unhomed_move"] = r.hex()
        # Enable cycle clears it.
        owner.exchange(command(0, 0x21, 0x20))
        owner.exchange(command(ENABLE, 0x21, 0x20))
        # A jog in position mode needs homing too (p.11): the same fault.
        owner.exchange(command(ENABLE | DIRECTION, **JOG))
        owner.send(command(ENABLE | DIRECTION | LOAD, **JOG))
        owner.wait_for(lambda r: r[0] & FAULT, 2.0)
        out["unhomed_jog"] = owner.read().hex()
        owner.exchange(command(0, 0x21, 0x20))
        out["after_enable_cycle"] = owner.exchange(command(ENABLE, 0x21, 0x20)).hex()

        # Velocity mode: target position 1000 is data only; Load/Start edges.
        out["set_velocity_mode"] = mode(d, 1)
        owner.exchange(command(ENABLE, 0x21, 0x20, 1000))
        r = owner.exchange(command(ENABLE | LOAD, 0x21, 0x20, 1000))
        out["loaded"] = r.hex()
        out["attr6_after_load"] = akd.raw(d, akd.GET, akd.POSITION_CONTROLLER, 1, 6)
        r = owner.exchange(command(ENABLE | LOAD, 0x21, 0x20, 2000))
        out["attr6_while_high"] = akd.raw(d, akd.GET, akd.POSITION_CONTROLLER, 1, 6)
        out["load_complete_while_high"] = r[2] & LOAD_COMPLETE
        r = owner.exchange(command(ENABLE, 0x21, 0x20, 2000))
        out["load_complete_after_clear"] = r[2] & LOAD_COMPLETE
        # An undefined command type: the error response.
        r = owner.exchange(command(ENABLE | LOAD, 0x2A, 0x25, 7))
        out["undefined_type"] = r.hex()
        owner.exchange(command(ENABLE, 0x2A, 0x25, 7))

        # Jog, positive then negative; Smooth Stop.
        owner.exchange(command(ENABLE | DIRECTION, **JOG))
        t0 = time.monotonic()
        owner.send(command(ENABLE | DIRECTION | LOAD, **JOG))
        out["jog_up_ms"] = owner.wait_for(lambda r: dint(r, 12) == 1000, 3.0)
        r = owner.read()
        out["jog_positive"] = r.hex()
        owner.send(command(ENABLE | DIRECTION | SMOOTH_STOP, **JOG))
        out["smooth_stop_ms"] = owner.wait_for(lambda r: r[0] & IN_MOTION == 0, 5.0)
        out["after_smooth_stop"] = owner.read().hex()
        owner.exchange(command(ENABLE, **JOG))
        owner.send(command(ENABLE | LOAD, **JOG))
        owner.wait_for(lambda r: dint(r, 12) == -1000, 3.0)
        out["jog_negative"] = owner.read().hex()
        # Hard Stop: stops, disables; no motion until an enable cycle.
        owner.send(command(ENABLE | HARD_STOP, **JOG))
        out["hard_stop_ms"] = owner.wait_for(lambda r: r[0] & IN_MOTION == 0, 5.0)
        out["after_hard_stop"] = owner.exchange(command(ENABLE, **JOG)).hex()
        owner.exchange(command(ENABLE | LOAD, **JOG), 200)
        out["load_without_cycle"] = owner.read().hex()
        owner.exchange(command(0, **JOG))
        owner.exchange(command(ENABLE, **JOG))
        owner.exchange(command(ENABLE | LOAD, **JOG), 200)
        out["load_after_cycle"] = owner.read().hex()
        # Target velocity 0 (type 2): the drive ramps down and the trajectory ends.
        owner.exchange(command(ENABLE, 0x22, 0x20, 0))
        owner.send(command(ENABLE | LOAD, 0x22, 0x20, 0))
        out["zero_velocity_ms"] = owner.wait_for(lambda r: r[0] & IN_MOTION == 0, 3.0)
        # The actual torque (response type 5) through a 10 rev/s² ramp to 1 rev/s: within
        # the drive's 20 A peak; 100 mA of friction at speed.
        ramp = dict(ctype=0x27, rtype=0x25, velocity=65536, accel=655360, decel=655360)
        owner.exchange(command(ENABLE | DIRECTION, **ramp))
        owner.send(command(ENABLE | DIRECTION | LOAD, **ramp))
        torques, t0 = [], time.monotonic()
        while time.monotonic() - t0 < 0.3:
            torques.append(dint(owner.read(), 4))
            time.sleep(0.002)
        out["ramp_torque_max"] = max(abs(t) for t in torques)
        out["speed_torque"] = dint(owner.read(), 4)
        owner.exchange(command(ENABLE, 0x22, 0x20, 0))
        owner.send(command(ENABLE | LOAD, 0x22, 0x20, 0))
        owner.wait_for(lambda r: r[0] & IN_MOTION == 0, 3.0)
        owner.exchange(command(ENABLE, 0x21, 0x20))

        # Attribute to Get: mode (attribute 3) mirrored every cycle, also after an
        # explicit change; torque response (type 5) in bytes 4-7.
        r = owner.exchange(command(ENABLE, 0x21, 0x25, attribute=3))
        out["attribute_to_get_velocity"] = r.hex()
        out["set_position_mode"] = mode(d, 0)
        out["mode_seen_ms"] = owner.wait_for(lambda r: r[32] == 3 and r[24] == 0, 1.0)

        # Homing through HOME.MOVE (0x0F/205/1 = 1), then an absolute move.
        out["home_move"] = akd.raw(d, akd.SET, akd.PARAMETER, 205, 1, b"\x01")
        out["homed_ms"] = owner.wait_for(lambda r: r[0] & HOMED, 10.0)
        move = dict(ctype=0x26, rtype=0x21, position=5000, velocity=2000, accel=20000,
                    decel=20000)
        owner.exchange(command(ENABLE, **move))
        owner.send(command(ENABLE | LOAD, **move))
        out["moving"] = owner.wait_for(lambda r: r[0] & IN_MOTION, 1.0) is not None
        # DRV.MOTIONSTAT while moving: bit 15 (inside MT.TPOSWND, 0.5 rev) does not wait
        # for the end of the move; bit 11 does.
        out["while_moving"] = owner.read().hex()
        out["move_ms"] = owner.wait_for(lambda r: r[0] & IN_MOTION == 0, 10.0)
        time.sleep(0.05)
        out["after_move"] = owner.read().hex()
        out["attr6_after_move"] = akd.raw(d, akd.GET, akd.POSITION_CONTROLLER, 1, 6)
        out["pl_fb"] = akd.raw(d, akd.GET, akd.PARAMETER, 1017, 1)
        # Relative: -1500 from there.
        rel = dict(move, position=-1500)
        owner.exchange(command(ENABLE, **rel))
        owner.send(command(ENABLE | LOAD | RELATIVE, **rel))
        owner.wait_for(lambda r: r[0] & IN_MOTION, 1.0)
        owner.wait_for(lambda r: r[0] & IN_MOTION == 0, 10.0)
        time.sleep(0.05)
        out["after_relative"] = owner.read().hex()
        # Motion task 3 (MT.NUM, MT.P, MT.V, MT.ACC, MT.DEC, then MT.SET), run by Start Block.
        task = [(1030, b"\x03"), (1031, struct.pack("<q", 1000)), (1033, struct.pack("<q", 2000)),
                (1035, struct.pack("<q", 20000)), (1037, struct.pack("<q", 20000)),
                (1040, b"\x01")]
        out["task_writes"] = [akd.raw(d, akd.SET, akd.PARAMETER, i, 1, v)["status"]
                              for i, v in task]
        owner.exchange(command(ENABLE, 0x21, 0x20, block=3))
        owner.send(command(ENABLE | START_BLOCK, 0x21, 0x20, block=3))
        owner.wait_for(lambda r: r[0] & BLOCK, 1.0)
        out["block_running"] = owner.read().hex()
        # A refused load (undefined command type) while the task runs: the task goes on.
        owner.exchange(command(ENABLE, 0x2A, 0x20, block=3))
        out["refused_during_task"] = owner.exchange(command(ENABLE | LOAD, 0x2A, 0x20,
                                                            block=3)).hex()
        owner.exchange(command(ENABLE, 0x21, 0x20, block=3))
        owner.wait_for(lambda r: r[0] & IN_MOTION == 0, 10.0)
        time.sleep(0.05)
        out["after_task"] = owner.read().hex()
        # Start Block of a task never stored: the error response 0x16, MOTIONSTAT bit 10.
        owner.exchange(command(ENABLE, 0x21, 0x20, block=9))
        out["undefined_task"] = owner.exchange(command(ENABLE | START_BLOCK, 0x21, 0x20,
                                                       block=9)).hex()
        owner.exchange(command(ENABLE, 0x21, 0x20))
        # Map type 2: EIP.RSPMAP (1043) lists PL.FB, DRV.MOTIONSTAT, EIP.PROFUNIT; the
        # response's bytes 36-63 carry them. EIP.CMDMAP (1042) lists MT.TPOSWND, written on
        # a Load/Start edge (command type 0x1F reading MT.TPOSWND carries the load).
        rspmap = struct.pack("<7H", 1017, 1010, 797, 0, 0, 0, 0)
        out["set_rspmap"] = akd.raw(d, akd.SET, akd.PARAMETER, 1043, 1, rspmap)["status"]
        out["rspmap"] = akd.raw(d, akd.GET, akd.PARAMETER, 1043, 1)
        out["rspmap_unknown"] = akd.raw(d, akd.SET, akd.PARAMETER, 1043, 1,
                                        struct.pack("<7H", 1017, 12, 0, 0, 0, 0, 0))["status"]
        out["dynamic_response"] = owner.exchange(command(ENABLE, 0x21, 0x20, map_type=2)).hex()
        out["set_cmdmap"] = akd.raw(d, akd.SET, akd.PARAMETER, 1042, 1,
                                    struct.pack("<7H", 1015, 0, 0, 0, 0, 0, 0))["status"]
        load_map = bytearray(command(ENABLE, 0x1F, 0x20, data=1015, map_type=2))
        load_map[36:40] = struct.pack("<i", 7)
        owner.exchange(bytes(load_map))
        load_map[0] |= LOAD
        r = owner.exchange(bytes(load_map))
        out["cmdmap_load_complete"] = r[2] & LOAD_COMPLETE
        out["tposwnd_after_map"] = akd.raw(d, akd.GET, akd.PARAMETER, 1015, 1)
        # A refused load (undefined command type 0x0A) carrying the map changes nothing.
        refused = bytearray(command(ENABLE, 0x0A, 0x20, map_type=2))
        refused[36:40] = struct.pack("<i", 99)
        owner.exchange(bytes(refused))
        refused[0] |= LOAD
        out["refused_map_load"] = owner.exchange(bytes(refused)).hex()
        out["tposwnd_after_refused"] = akd.raw(d, akd.GET, akd.PARAMETER, 1015, 1)
        # Disable at the end.
        out["disabled"] = owner.exchange(command(0, 0x21, 0x20)).hex()
    finally:
        out["forward_close"] = owner.close()
        owner.release()
        d.close()
    # Admission: the manual's minimum RPI, and multicast T->O.
    short = akd.Owner(enip, ip, 5, mult)
    out["rpi_5ms"] = short.open()
    short.release()
    multicast = akd.Owner(enip, ip, rpi, mult)
    out["multicast_open"] = multicast.open(multicast=True)
    if out["multicast_open"] == 0:
        out["multicast_close"] = multicast.close()
    multicast.release()
    enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
