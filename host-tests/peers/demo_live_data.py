"""Demo, live data: an exclusive-owner Class 1 connection with the PyPI `ethernetip`
package (generic profile: input 100, output 150, config 151). Once a second it puts a new
counter in its output (O->T) data and prints the input (T->O) data the board produces,
which on the generic profile echoes the output.

Usage: python demo_live_data.py BOARD_IP RPI_MS SECONDS
"""
import sys
import time

from generic_owner import CONFIG, INPUT, OUTPUT, put, start, to_bytes

ip, rpi, seconds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])

enip, conn, inp, out = start(ip)
try:
    status = conn.sendFwdOpenReq(INPUT, OUTPUT, CONFIG, torpi=rpi, otrpi=rpi, multiplier=1)
    if status != 0:
        sys.exit(f"Forward_Open refused (status {status:#x})")
    print(f"Class 1 data (ethernetip, exclusive owner, RPI {rpi} ms): O->T out, T->O in")
    conn.produce()
    for second in range(1, seconds + 1):  # bounded
        put(out, bytes([second] * 4 + [0] * 28))
        time.sleep(1)
        print(f"  t={second:2d}s  out {bytes([second] * 4).hex(' ')} ..  "
              f"in {to_bytes(inp)[:8].hex(' ')} ..", flush=True)
    conn.stopProduce()
    time.sleep(0.05)
    conn.sendFwdCloseReq(INPUT, OUTPUT, CONFIG)
finally:
    enip.stopIO()
