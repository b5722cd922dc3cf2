"""``python -m mechgen``: the same as the ``mechgen`` command."""
import sys

from .cli import main

sys.exit(main())
