"""One explicit request through pycomm3 (unconnected, or Class 3 connected), shared by the
peers that send raw CIP requests: the reply's general status and data, whatever they are.

Not a peer itself: the scenario scripts import it (their directory is on sys.path).
"""


def request(driver, service, cls, instance, attribute, data=b"", connected=False):
    """One request; returns (general status or None, reply bytes)."""
    # pycomm3 drops an integer attribute 0, so attribute ids travel as bytes.
    tag = driver.generic_message(service=service, class_code=cls, instance=instance,
                                 attribute=b"" if attribute is None else bytes([attribute]),
                                 request_data=data, connected=connected,
                                 unconnected_send=False, route_path=False,
                                 return_response_packet=True,
                                 name=f"{cls:x}/{instance}/{attribute}")
    response = tag.value
    if response is None:
        return None, b""
    value = response.value if isinstance(response.value, (bytes, bytearray)) else b""
    return response.service_status, bytes(value)


def raw(driver, service, cls, instance, attribute, data=b""):
    """One unconnected request; {"status": general status or None, "data": reply hex}."""
    status, value = request(driver, service, cls, instance, attribute, data)
    return {"status": status, "data": value.hex()}
