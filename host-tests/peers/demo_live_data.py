"""Demo, live data: an exclusive-owner Class 1 connection with the PyPI `ethernetip`
package (generic profile: input 100, output 150, config 151). Once a second it puts a new
counter in its output (O->T) data and prints the input (T->O) data the board produces,
which on the generic profile echoes the output.

Usage: python demo_live_data.py BOARD_IP RPI_MS SECONDS
"""
import sys
import time

import ethernetip.ethernetip as enip_mod
from ethernetip.ethernetip import EtherNetIP

# Its producer never runs faster than this many ms otherwise.
enip_mod.config.UDP_IO_MIN_RPI = 0

ip, rpi, seconds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])


def to_bytes(bits):
    return bytes(sum(1 << b for b in range(8) if bits[i * 8 + b]) for i in range(len(bits) // 8))


def put(bits, data):
    for i, byte in enumerate(data):
        for b in range(8):
            bits[i * 8 + b] = bool(byte & (1 << b))


enip = EtherNetIP(ip)
conn = enip.explicit_conn(ip)
conn.registerSession()
inp = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_INPUT, 32, 100, conn)
out = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_OUTPUT, 32, 150, conn)
enip.startIO()
try:
    status = conn.sendFwdOpenReq(100, 150, 151, torpi=rpi, otrpi=rpi, multiplier=1)
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
    conn.sendFwdCloseReq(100, 150, 151)
finally:
    enip.stopIO()
