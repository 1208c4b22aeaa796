#!/usr/bin/python3
"""Write what is generated from mapnav's option tables (core/include/mapnav/core/option_table.h).

    update_option_docs.py [MAPNAV]

MAPNAV is the built tool (default: build/bin/mapnav). Writes
  maps/schema/mapnav-options-1.schema.json   `mapnav options --schema`, indented
  docs/options.md                            `mapnav options --markdown`
and replaces the option definitions in maps/schema/mapnav-mission-1.schema.json's $defs (every
definition that schema refers to, directly or through another) with the generated ones.
tests/apps/options_cli_test.cpp fails when a committed file differs from what the tables say; run
this after changing an option's default, rule or doc, and commit the files it changes.
"""

import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def refs(node):
    """Every "#/$defs/NAME" a JSON Schema node refers to."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key == "$ref" and isinstance(value, str) and value.startswith("#/$defs/"):
                yield value[len("#/$defs/"):].split("/")[0]
            else:
                yield from refs(value)
    elif isinstance(node, list):
        for value in node:
            yield from refs(value)


def write_json(path, doc):
    with open(path, "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=2, ensure_ascii=False)
        f.write("\n")


def main(argv):
    tool = argv[1] if len(argv) > 1 else os.path.join(ROOT, "build/bin/mapnav")
    if not os.access(tool, os.X_OK):
        sys.stderr.write(f"update_option_docs.py: {tool}: not an executable (build mapnav first)\n")
        return 2
    options = json.loads(subprocess.run([tool, "options", "--schema"], check=True, capture_output=True, text=True).stdout)
    markdown = subprocess.run([tool, "options", "--markdown"], check=True, capture_output=True, text=True).stdout
    write_json(os.path.join(ROOT, "maps/schema/mapnav-options-1.schema.json"), options)
    with open(os.path.join(ROOT, "docs/options.md"), "w", encoding="utf-8") as f:
        f.write(markdown)

    mission_path = os.path.join(ROOT, "maps/schema/mapnav-mission-1.schema.json")
    with open(mission_path, encoding="utf-8") as f:
        mission = json.load(f)
    generated = options["$defs"]
    defs = mission.setdefault("$defs", {})
    pending, done = [name for name in refs(mission.get("properties", {})) if name in generated], set()
    while pending:
        name = pending.pop()
        if name in done:
            continue
        done.add(name)
        defs[name] = generated[name]
        pending.extend(n for n in refs(generated[name]) if n in generated)
    mission["$defs"] = dict(sorted(defs.items()))
    write_json(mission_path, mission)
    print("update_option_docs.py: wrote maps/schema/mapnav-options-1.schema.json, docs/options.md and the "
          "option definitions of maps/schema/mapnav-mission-1.schema.json")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
