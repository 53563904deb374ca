"""CIP Security peer (tests/cip_security.rs): reads a JSON list of steps on stdin and prints
one JSON line with each step's outcome.

Steps ("do"):
  tls_identity  pycomm3 CIPDriver whose socket Python's ssl wraps (TLS 1.2, the given suites
                and client certificate, the key log written for tshark) reads the Identity
                object unconnected (Get_Attributes_All) and over a Class 3 connection
                (Forward_Open, Get_Attribute_Single, Forward_Close); reports the protocol
                version, the suite and the product name, or the handshake's error.
  tls_message   pycomm3 over TLS as above sends one unconnected request (service, class,
                instance, data hex): reports its error (None on success).
  plain_register  a RegisterSession on plaintext 44818: reports whether it was served.
  plaintext     a RegisterSession in plaintext to TLS port 2221: reports whether any
                EtherNet/IP reply came back (it must not).
  request       a raw UCMM request over plaintext 44818 (one session per step list): service,
                class, instance, optional attribute, data (hex); reports the general status,
                the extended status words and the reply data (hex).
  list_identity ListIdentity over TCP 44818: the reply's items (type, data hex).
  capacity      the 3 sessions shared by 44818 and 2221: two plaintext sessions and one
                over TLS are served, a fourth is refused on either port, and once the TLS
                one closes a new TLS session is served again.
  pycomm3_list_identity  pycomm3's own ListIdentity (CIPDriver.list_identity): the product
                name it parsed from a reply that carries the CIP Security item too.
"""
import json
import socket
import ssl
import struct
import sys
import time

from pycomm3 import CIPDriver, Services
import pycomm3.cip_driver as cip_driver_module
import pycomm3.socket_ as socket_module


def tls_context(step):
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    ctx.minimum_version = ssl.TLSVersion.TLSv1_2
    ctx.maximum_version = ssl.TLSVersion.TLSv1_2
    ctx.set_ciphers(step.get("ciphers", "ECDHE-ECDSA-AES128-SHA256"))
    ctx.check_hostname = False
    ctx.load_verify_locations(step["server_ca"])
    if step.get("client_cert"):
        ctx.load_cert_chain(step["client_cert"], step["client_key"])
    if step.get("keylog"):
        ctx.keylog_filename = step["keylog"]
    return ctx


def tls_identity(host, step):
    ctx = tls_context(step)
    seen = {}

    class TlsSocket(socket_module.Socket):
        def connect(self, host, port):
            self.sock.connect((host, port))
            self.sock = ctx.wrap_socket(self.sock)
            seen["version"] = self.sock.version()
            seen["cipher"] = self.sock.cipher()[0]

    cip_driver_module.Socket = TlsSocket
    try:
        with CIPDriver(f"{host}:2221") as drv:
            all_ = drv.generic_message(
                service=Services.get_attributes_all, class_code=1, instance=1,
                connected=False, unconnected_send=False, route_path=False, name="identity")
            if all_.error:
                return {"ok": False, "error": f"identity: {all_.error}", **seen}
            data = all_.value
            name = data[15:15 + data[14]].decode("ascii", "replace")
            conn = drv.generic_message(
                service=Services.get_attribute_single, class_code=1, instance=1,
                attribute=b"\x07", connected=True, unconnected_send=False,
                route_path=False, name="connected")
            connected = None if conn.error else conn.value[1:1 + conn.value[0]].decode()
            return {"ok": True, "product_name": name, "connected_name": connected,
                    "connected_error": conn.error, **seen}
    except Exception as e:  # the handshake or the connection failed
        return {"ok": False, "error": f"{type(e).__name__}: {e}", **seen}


def tls_message(host, step):
    ctx = tls_context(step)

    class TlsSocket(socket_module.Socket):
        def connect(self, host, port):
            self.sock.connect((host, port))
            self.sock = ctx.wrap_socket(self.sock)

    cip_driver_module.Socket = TlsSocket
    try:
        with CIPDriver(f"{host}:2221") as drv:
            r = drv.generic_message(
                service=step["service"], class_code=step["class"], instance=step["instance"],
                request_data=bytes.fromhex(step["data"]), connected=False,
                unconnected_send=False, route_path=False, name="message")
            return {"error": r.error}
    except Exception as e:
        return {"error": f"{type(e).__name__}: {e}"}


def plain_register(host):
    try:
        s = socket.create_connection((host, 44818), timeout=3)
        ok = register(s)
        s.close()
        return {"served": ok}
    except OSError as e:
        return {"served": False, "error": str(e)}


def enip(command, data=b"", session=0):
    return struct.pack("<HHII8sI", command, len(data), session, 0, b"cipsec\0\0", 0) + data


def recv_frame(s):
    buf = b""
    while len(buf) < 24:
        chunk = s.recv(4096)
        if not chunk:
            return None
        buf += chunk
    need = 24 + struct.unpack_from("<H", buf, 2)[0]
    while len(buf) < need:
        chunk = s.recv(4096)
        if not chunk:
            return None
        buf += chunk
    return buf


def plaintext(host):
    try:
        s = socket.create_connection((host, 2221), timeout=3)
        s.sendall(enip(0x65, struct.pack("<HH", 1, 0)))
        reply = recv_frame(s)
        s.close()
        return {"enip_reply": reply is not None and reply[:2] == b"\x65\x00"}
    except OSError as e:
        return {"enip_reply": False, "error": str(e)}


def register(sock):
    sock.sendall(enip(0x65, struct.pack("<HH", 1, 0)))
    reply = recv_frame(sock)
    return reply is not None and reply[:2] == b"\x65\x00" and reply[8:12] == b"\0\0\0\0"


def capacity(host, step):
    ctx = tls_context(step)

    def session(port):
        raw = socket.create_connection((host, port), timeout=3)
        sock = ctx.wrap_socket(raw) if port == 2221 else raw
        if not register(sock):
            sock.close()
            raise OSError("no RegisterSession reply")
        return sock

    def refused(port):
        try:
            session(port).close()
            return False
        except (OSError, ssl.SSLError):
            return True

    held = [session(44818), session(44818), session(2221)]
    out = {"fourth_tls_refused": refused(2221), "fourth_plain_refused": refused(44818)}
    held.pop().close()
    out["tls_again"] = False
    deadline = time.monotonic() + 3
    while time.monotonic() < deadline and not out["tls_again"]:
        try:
            session(2221).close()
            out["tls_again"] = True
        except (OSError, ssl.SSLError):
            time.sleep(0.1)
    for sock in held:
        sock.close()
    return out


class Raw:
    """A minimal UCMM client over plaintext 44818, for exact statuses."""

    def __init__(self, host):
        self.s = socket.create_connection((host, 44818), timeout=3)
        self.s.sendall(enip(0x65, struct.pack("<HH", 1, 0)))
        self.session = struct.unpack_from("<I", recv_frame(self.s), 4)[0]

    def request(self, step):
        path = bytes([0x20, step["class"]]) if step["class"] < 256 else \
            bytes([0x21, 0]) + struct.pack("<H", step["class"])
        path += bytes([0x24, step["instance"]])
        if "attribute" in step:
            path += bytes([0x30, step["attribute"]])
        mr = bytes([step["service"], len(path) // 2]) + path + bytes.fromhex(step.get("data", ""))
        cpf = struct.pack("<IHH", 0, 0, 2) + struct.pack("<HH", 0, 0) + \
            struct.pack("<HH", 0xB2, len(mr)) + mr
        self.s.sendall(enip(0x6F, cpf, self.session))
        reply = recv_frame(self.s)
        mr = reply[24 + 16:]
        general, words = mr[2], mr[3]
        ext = [struct.unpack_from("<H", mr, 4 + 2 * i)[0] for i in range(words)]
        return {"status": general, "ext": ext, "data": mr[4 + 2 * words:].hex()}

    def list_identity(self):
        self.s.sendall(enip(0x63))
        reply = recv_frame(self.s)
        items, at = [], 26
        for _ in range(struct.unpack_from("<H", reply, 24)[0]):
            kind, length = struct.unpack_from("<HH", reply, at)
            items.append([kind, reply[at + 4:at + 4 + length].hex()])
            at += 4 + length
        return {"items": items}


def main():
    job = json.load(sys.stdin)
    host = job["host"]
    raw = None
    out = []
    for step in job["steps"]:
        do = step["do"]
        if do == "tls_identity":
            out.append(tls_identity(host, step))
        elif do == "plaintext":
            out.append(plaintext(host))
        elif do == "tls_message":
            out.append(tls_message(host, step))
        elif do == "plain_register":
            out.append(plain_register(host))
        elif do == "capacity":
            out.append(capacity(host, step))
        elif do == "pycomm3_list_identity":
            found = CIPDriver.list_identity(host) or {}
            out.append({"product_name": found.get("product_name")})
        else:
            raw = raw or Raw(host)
            out.append(raw.request(step) if do == "request" else raw.list_identity())
    print(json.dumps(out))


if __name__ == "__main__":
    main()
