#!/usr/bin/env python3
"""Validates JSON files against a JSON Schema (Debian package python3-jsonschema).

usage: validate_json_schema.py <schema.json> <instance.json>...

Checks the schema itself against its draft's meta-schema, then each instance. Prints one line
per instance, "<file>: valid" or "<file>: invalid", followed by one indented line per error
("  at /tests/tap~1x/modes/0/fn_hz: '898' is not of type 'number'"). Exit status: 0 when every
instance is valid, 1 when any is invalid, 2 for an unusable schema or unreadable file, 3 when
the jsonschema module is missing.
"""
import json
import sys

try:
    import jsonschema
except ImportError:
    print("python3 module 'jsonschema' is missing: install the Debian package python3-jsonschema "
          "(scripts/install-deps.sh)")
    sys.exit(3)


def pointer(path):
    return "/" + "/".join(str(p).replace("~", "~0").replace("/", "~1") for p in path)


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    try:
        with open(argv[1]) as f:
            schema = json.load(f)
        cls = jsonschema.validators.validator_for(schema)
        cls.check_schema(schema)
    except (OSError, ValueError, jsonschema.exceptions.SchemaError) as e:
        print(f"{argv[1]}: unusable schema: {e}")
        return 2
    validator = cls(schema)
    status = 0
    for name in argv[2:]:
        try:
            with open(name) as f:
                instance = json.load(f)
        except (OSError, ValueError) as e:
            print(f"{name}: unreadable: {e}")
            return 2
        errors = sorted(validator.iter_errors(instance), key=lambda e: list(map(str, e.absolute_path)))
        print(f"{name}: {'valid' if not errors else 'invalid'}")
        for e in errors:
            message = e.message if len(e.message) <= 300 else e.message[:300] + " ..."
            print(f"  at {pointer(e.absolute_path)}: {message}")
        if errors:
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
