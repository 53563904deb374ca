"""Attribute reads and writes with cpppo's client proxy (cpppo.server.enip.get_attribute).

Reads one JSON document from stdin:
  {"host": "198.18.0.2", "route": "direct" | "default",
   "ops": [{"name": str, "path": "@class/instance/attribute", "type": "INT" | ...,
            "values": null | [int, ...]}]}
"direct" uses proxy_simple (no route path, no send path: plain UCMM); "default" uses proxy
with cpppo's default Unconnected_Send route path (port 1, link 0). An op with "values" is a
Set_Attribute_Single of those values; without, a Get_Attribute_Single decoded as "type".
Prints one JSON line: {"identity": product name from cpppo's ListIdentity or null,
"results": [{"name", "status", "value"}]}.
"""
import contextlib
import json
import sys

from cpppo.server.enip.get_attribute import proxy, proxy_simple


def attribute(op):
    if op.get("values") is None:
        return (op["path"], op["type"])
    values = ",".join(str(v) for v in op["values"])
    return ("%s=(%s)%s" % (op["path"], op["type"], values), op["type"])


def jsonable(value):
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, (bool, int, float, str)) or value is None:
        return value
    return str(value)


def main():
    spec = json.load(sys.stdin)
    cls = proxy_simple if spec["route"] == "direct" else proxy
    via = cls(spec["host"], timeout=5)
    results = []
    with via:
        ops = [attribute(op) for op in spec["ops"]]
        with contextlib.closing(via.read_details(ops)) as reader:
            for op, (value, (status, _)) in zip(spec["ops"], reader):
                results.append({"name": op["name"], "status": status, "value": jsonable(value)})
        identity = getattr(via.identity, "product_name", None) if via.identity else None
    via.close_gateway()
    print(json.dumps({"identity": identity, "results": results}))


if __name__ == "__main__":
    main()
