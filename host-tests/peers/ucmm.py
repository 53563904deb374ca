"""One unconnected (UCMM) request through pycomm3, shared by the peers that send raw CIP
requests: the reply's general status and data, whatever they are.

Not a peer itself: the scenario scripts import it (their directory is on sys.path).
"""


def raw(driver, service, cls, instance, attribute, data=b""):
    """One UCMM request; {"status": general status or None, "data": reply hex}."""
    # pycomm3 drops an integer attribute 0, so attribute ids travel as bytes.
    tag = driver.generic_message(service=service, class_code=cls, instance=instance,
                                 attribute=b"" if attribute is None else bytes([attribute]),
                                 request_data=data, connected=False, unconnected_send=False,
                                 route_path=False, return_response_packet=True, name="raw")
    response = tag.value
    value = response.value if response is not None else b""
    return {"status": getattr(response, "service_status", None),
            "data": bytes(value).hex() if isinstance(value, (bytes, bytearray)) else ""}
