"""Checks the Kollmorgen AKD profile's EDS file with the PyPI `eds-pie` package, which logs
warnings and errors instead of raising: every record at WARNING or above is collected.

Reads {"path"} on stdin. Prints one JSON line: {"problems": [...], "protocol", "assemblies":
{name: size}, "connections": [[name, o2t_size, t2o_size, path]]}.
"""
import json
import logging
import sys


class Collect(logging.Handler):
    def __init__(self):
        super().__init__(logging.WARNING)
        self.problems = []

    def emit(self, record):
        self.problems.append(f"{record.levelname}: {record.getMessage()}")


def main():
    path = json.load(sys.stdin)["path"]
    collect = Collect()
    logging.getLogger().addHandler(collect)
    from eds_pie.eds_pie import CIP_EDS  # after the handler: it logs while importing too

    with open(path, "rb") as f:
        eds = CIP_EDS(f.read())
    assemblies = {
        keyword: eds.get_value("Assembly", keyword, 2)
        for keyword in eds.get_section("Assembly").entries
        if keyword.startswith("Assem")
    }
    connections = [
        [eds.get_value("Connection Manager", k, 12), eds.get_value("Connection Manager", k, 3),
         eds.get_value("Connection Manager", k, 6), eds.get_value("Connection Manager", k, 14)]
        for k in eds.get_section("Connection Manager").entries
        if k.startswith("Connection")
    ]
    print(json.dumps({"problems": collect.problems, "protocol": eds.protocol,
                      "assemblies": assemblies, "connections": connections}, default=str))


if __name__ == "__main__":
    main()
