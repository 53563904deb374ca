"""Shared by ethernetip_class1.py and demo_live_data.py (not a peer itself): the PyPI
`ethernetip` package as an exclusive owner of the generic profile (input 100, output 150,
configuration 151, 32 bytes each way), and the package's bit-list data as bytes."""
import ethernetip.ethernetip as enip_mod
from ethernetip.ethernetip import EtherNetIP

# Its producer never runs faster than this many ms otherwise.
enip_mod.config.UDP_IO_MIN_RPI = 0

INPUT, OUTPUT, CONFIG = 100, 150, 151
SIZE = 32


def start(ip):
    """(enip, conn, inp, out): a session with `ip`, the input and output assemblies
    registered as bit lists, I/O started (the caller stops it with enip.stopIO())."""
    enip = EtherNetIP(ip)
    conn = enip.explicit_conn(ip)
    conn.registerSession()
    inp = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_INPUT, SIZE, INPUT, conn)
    out = enip.registerAssembly(EtherNetIP.ENIP_IO_TYPE_OUTPUT, SIZE, OUTPUT, conn)
    enip.startIO()
    return enip, conn, inp, out


def to_bytes(bits):
    """The bytes of a bit list (bit 0 of byte 0 first)."""
    return bytes(sum(1 << b for b in range(8) if bits[i * 8 + b]) for i in range(len(bits) // 8))


def put(bits, data):
    """Writes `data` into the bit list `bits`."""
    for i, byte in enumerate(data):
        for b in range(8):
            bits[i * 8 + b] = bool(byte & (1 << b))
