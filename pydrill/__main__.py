"""``python -m pydrill`` is the ``pydrill`` command."""

from .cli import main

if __name__ == "__main__":
    raise SystemExit(main())
