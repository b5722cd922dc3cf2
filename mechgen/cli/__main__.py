"""``python -m mechgen.cli``: the same as the ``mechgen`` command."""
import sys

from . import main

sys.exit(main())
