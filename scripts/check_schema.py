#!/usr/bin/python3
"""Check JSON files against a JSON Schema (draft 2020-12).

    check_schema.py SCHEMA FILE...
    check_schema.py --expect SCHEMA FILE...

Prints one line per file: `FILE: ok`, or `FILE: invalid: MESSAGE at POINTER` with the schema's
first (most relevant) complaint and the JSON pointer of the offending value ("" is the whole
document; for an unknown member, the pointer of that member). Exits 0 when every file is valid,
1 otherwise, 2 on a usage error or an unreadable schema.

With --expect, each file may carry `"x-expect": {"schema_rejects": true|false, ...}` (the invalid map
fixtures in tests/data/maps do): a file passes when the schema's verdict matches it (a file without
x-expect must be valid). Lines read `FILE: ok (rejected as expected: ...)` or `FILE: FAIL: ...`;
exit 0 when every file passes.

Needs the `jsonschema` Python package (Debian: python3-jsonschema), so run it with the system
Python (/usr/bin/python3), not a virtualenv or pyenv one without that package.
"""

import json
import math
import re
import sys

try:
    import jsonschema
    from jsonschema.exceptions import best_match
except ImportError:  # pragma: no cover
    sys.stderr.write("check_schema.py: the Python package jsonschema is missing "
                     "(apt-get install python3-jsonschema; run with /usr/bin/python3)\n")
    sys.exit(2)


def _finite_float(text):
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"number {text} is not finite")
    return v


def _reject_constant(name):
    raise ValueError(f"{name} is not JSON")


def load_json(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f, parse_float=_finite_float, parse_constant=_reject_constant)


def pointer(parts):
    return "".join("/" + str(p).replace("~", "~0").replace("/", "~1") for p in parts)


def describe(error):
    """(message, pointer) for a jsonschema ValidationError."""
    path = list(error.absolute_path)
    if error.validator == "additionalProperties" and isinstance(error.instance, dict):
        # Point at the first unexpected member rather than at the object holding it.
        schema = error.schema
        known = set(schema.get("properties", {}))
        patterns = [re.compile(p) for p in schema.get("patternProperties", {})]
        extra = [k for k in error.instance if k not in known and not any(p.search(k) for p in patterns)]
        if extra:
            path.append(extra[0])
    return error.message, pointer(path)


def check(validator, path):
    """None if the file is valid, else a description of the first problem."""
    try:
        doc = load_json(path)
    except (OSError, UnicodeDecodeError) as e:
        return None, f"cannot read: {e}"
    except ValueError as e:  # json.JSONDecodeError is a ValueError
        return None, f"not JSON: {e}"
    err = best_match(validator.iter_errors(doc))
    if err is None:
        return doc, None
    message, where = describe(err)
    return doc, f"{message} at {where}"


def main(argv):
    args = argv[1:]
    expect = False
    if args and args[0] == "--expect":
        expect = True
        args = args[1:]
    if len(args) < 2 or args[0] in ("-h", "--help"):
        sys.stderr.write(__doc__)
        return 2
    schema_path, files = args[0], args[1:]
    try:
        schema = load_json(schema_path)
        jsonschema.Draft202012Validator.check_schema(schema)
    except (OSError, ValueError, jsonschema.exceptions.SchemaError) as e:
        sys.stderr.write(f"{schema_path}: bad schema: {e}\n")
        return 2
    validator = jsonschema.Draft202012Validator(schema)

    all_ok = True
    for path in files:
        doc, problem = check(validator, path)
        if not expect:
            if problem is None:
                print(f"{path}: ok")
            else:
                print(f"{path}: invalid: {problem}")
                all_ok = False
            continue
        want_reject = False
        if isinstance(doc, dict) and isinstance(doc.get("x-expect"), dict):
            want_reject = bool(doc["x-expect"].get("schema_rejects", False))
        if want_reject and problem is not None:
            print(f"{path}: ok (rejected as expected: {problem})")
        elif not want_reject and problem is None:
            print(f"{path}: ok")
        elif want_reject:
            print(f"{path}: FAIL: the schema accepts it but x-expect.schema_rejects is true")
            all_ok = False
        else:
            print(f"{path}: FAIL: invalid: {problem}")
            all_ok = False
    return 0 if all_ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
