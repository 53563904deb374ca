"""Explicit (UCMM) requests with pycomm3's CIPDriver.generic_message.

Reads one JSON document from stdin:
  {"host": "198.18.0.2",
   "requests": [{"name": str, "service": int, "class": int, "instance": int,
                 "attribute": int | null, "data": hex str, "route": null | "1/0"}]}
"route" null sends the request directly; "1/0" wraps it in Unconnected_Send with that path.
Prints one JSON line: {"results": [{"name", "status", "data", "error"}]} where "status" is
the CIP general status pycomm3 decoded (null if no reply) and "data" the reply data in hex.
"""
import json
import sys

from pycomm3 import CIPDriver


def run(driver, req):
    # pycomm3 drops an integer attribute 0, so attribute ids travel as bytes.
    attribute = b"" if req.get("attribute") is None else bytes([req["attribute"]])
    route = req.get("route")
    tag = driver.generic_message(
        service=req["service"],
        class_code=req["class"],
        instance=req["instance"],
        attribute=attribute,
        request_data=bytes.fromhex(req.get("data", "")),
        name=req["name"],
        connected=False,
        unconnected_send=route is not None,
        route_path=route if route is not None else False,
        return_response_packet=True,
    )
    response = tag.value
    value = response.value if response is not None else None
    return {
        "name": req["name"],
        "status": getattr(response, "service_status", None),
        "data": value.hex() if isinstance(value, (bytes, bytearray)) else "",
        "error": tag.error,
    }


def main():
    spec = json.load(sys.stdin)
    with CIPDriver(spec["host"]) as driver:
        results = [run(driver, r) for r in spec["requests"]]
    print(json.dumps({"results": results}))


if __name__ == "__main__":
    main()
