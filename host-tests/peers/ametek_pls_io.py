"""The 7500 PLS limit switch over Class 1 (PyPI `ethernetip`, exclusive owner 150/100 at the
given RPI), configured with pycomm3: output status at known positions (home offsets on a
stationary resolver), forces and group forces with the manual's precedence, Run Enable 0,
the add-on test (timed, and held by the enable bit), and a soft input reset to preset.

Reads {"host", "rpi_ms", "multiplier"} on stdin. Prints one JSON line.
"""
import json
import sys
import time

from pycomm3 import CIPDriver

import ametek_pls_common as pls


def output_bits(w):
    return w[10] | w[11] << 16


def changes(owner, t_from, t_to):
    """Times (ms since t0) at which output 1 changed, between t_from and t_to."""
    last, times = None, []
    for t, data in list(owner.samples):
        bit = pls.words(data)[10] & 1
        if last is not None and bit != last and t_from <= t <= t_to:
            times.append(round(t, 1))
        last = bit
    return times


def main():
    req = json.load(sys.stdin)
    ip, rpi, mult = req["host"], req["rpi_ms"], req["multiplier"]
    out = {}
    with CIPDriver(ip) as driver:
        out["writes"] = pls.write_program(driver)
        enip, owner = pls.start_owner(ip, rpi, mult)
        now = lambda: (time.monotonic() - owner.t0) * 1000.0

        def state(w):
            owner.send(w)
            owner.settle(rpi)
            return output_bits(owner.words())

        try:
            out["forward_open"] = owner.run(rpi)
            out["words_at_open"] = owner.words()
            positions = []
            for pos in (150, 250, 315, 55):
                status = pls.home(driver, pos)
                owner.wait_words(lambda d: d[0] == pos, 2.0)
                owner.settle(rpi)
                w = owner.words()
                positions.append([status, w[0], w[10] & 1, w[11] & 1])
            out["positions"] = positions
            pls.home(driver, 250)
            out["force_on_at_250"] = state([pls.RUN, 0b01])
            pls.home(driver, 150)
            out["force_off_at_150"] = state([pls.RUN, 0b10])
            out["group_on_over_force_off"] = state([pls.RUN, 0b10, 0, 0b10, 0, 0b01])
            out["group_off_over_force_on"] = state([pls.RUN, 0b01, 0, 0b01, 0, 0b10])
            pls.home(driver, 250)
            out["word4_forces_17"] = state([pls.RUN, 0, 0, 0b01])
            pls.home(driver, 150)
            out["run_enable_0"] = state([0, 0b01, 0, 0b01, 0, 0b01])
            out["run_enable_1"] = state([pls.RUN])
            # Add-on test at position 250 (output 1 off), 60 RPM, 1500 ms, output 1.
            pls.home(driver, 250)
            out["addon_write"] = pls.set_words(driver, 35, [60, 1500, 0x0001])
            out["before_addon"] = state([pls.RUN])
            t_start = now()
            owner.send([pls.RUN | pls.ADDON])
            time.sleep(2.8)
            out["timed"] = {"start": round(t_start, 1), "changes": changes(owner, t_start, now()),
                            "end": round(now(), 1)}
            out["addon_write_held"] = pls.set_words(driver, 35, [60, 0, 0x0001])
            owner.send([pls.RUN])
            owner.settle(rpi)
            t_start = now()
            owner.send([pls.RUN | pls.ADDON])
            time.sleep(2.5)
            t_clear = now()
            owner.send([pls.RUN])
            time.sleep(1.0)
            out["held"] = {"start": round(t_start, 1), "clear": round(t_clear, 1),
                           "changes": changes(owner, t_start, now()), "end": round(now(), 1),
                           "final": owner.words()[10] & 1}
            # Soft input 9: reset to preset group (type 120) to 77 on its rising edge.
            inputs = [0] * 112
            inputs[56:63] = [0b011, 0, 0, 120, 77, 0, 0]
            out["input_write"] = pls.set_words(driver, 34, inputs)
            pls.home(driver, 150)
            owner.send([pls.RUN, 0, 0, 0, 0, 0, 1])
            out["preset_on_edge"] = owner.wait_words(lambda d: d[0] == 77, 2.0) is not None
            pls.home(driver, 150)
            owner.settle(rpi)
            out["held_high"] = owner.words()[0]
            owner.send([pls.RUN, 0, 0, 0, 0, 0, 0])
            owner.settle(rpi)
            out["falling"] = owner.words()[0]
            owner.send([pls.RUN, 0, 0, 0, 0, 0, 1])
            out["second_edge"] = owner.wait_words(lambda d: d[0] == 77, 2.0) is not None
            out["input_status_9"] = pls.get_words(driver, pls.STATUS, 2)[24:27]
            out["offsets"] = pls.get_words(driver, pls.STATUS, 3)
        finally:
            out["forward_close"] = owner.close()
            enip.stopIO()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
