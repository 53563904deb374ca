"""An IPv4 packet carrying one TCP segment, built by hand for the peers that forge segments
on an AF_PACKET socket (`frame_storm.py`, `tcp_injection.py`): both checksums filled."""
import struct


def checksum(data):
    """The Internet checksum (RFC 1071) of `data`."""
    if len(data) % 2:
        data += b"\0"
    total = sum(struct.unpack("!%dH" % (len(data) // 2), data))
    while total > 0xFFFF:
        total = (total & 0xFFFF) + (total >> 16)
    return ~total & 0xFFFF


def ipv4_tcp(src_ip, dst_ip, ports, seq, ack, flags, ident, payload=b"", mss=None):
    """IPv4 header and TCP segment from `src_ip` to `dst_ip` (4 bytes each), `ports` a
    (source, destination) pair, with the MSS option if `mss` is given."""
    options = struct.pack("!BBH", 2, 4, mss) if mss is not None else b""
    offset = (20 + len(options)) // 4
    tcp = struct.pack("!HHIIBBHHH", ports[0], ports[1], seq, ack, offset << 4, flags, 64240,
                      0, 0) + options + payload
    pseudo = src_ip + dst_ip + struct.pack("!BBH", 0, 6, len(tcp))
    tcp = tcp[:16] + struct.pack("!H", checksum(pseudo + tcp)) + tcp[18:]
    ip = struct.pack("!BBHHHBBH4s4s", 0x45, 0, 20 + len(tcp), ident & 0xFFFF, 0, 64, 6, 0,
                     src_ip, dst_ip)
    return ip[:10] + struct.pack("!H", checksum(ip)) + ip[12:] + tcp
