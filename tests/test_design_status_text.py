"""A design table's ``tab.status`` holds the codes of mechgen.protocol; ``tab.status_text``
says them in words, and ``DesignTable.status``'s docstring explains the codes."""
import warnings

import numpy as np

from mechgen import protocol
from mechgen.runtime.tables.design import DesignTable


def test_status_text_says_the_codes(fourbar):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")         # the table warns that designs failed
        tab = fourbar.sweep(0, 1, 21, params={"a": [0.8, 1.0, 2.5]}, level="velocity")
    status, text = tab.status, tab.status_text
    assert text.shape == status.shape == tab.shape
    assert status[0] == protocol.OK and text[0] == "ok"
    assert status[-1] != protocol.OK        # a crank of 2.5 cannot turn: the loop opens
    assert text[-1] == protocol.STATUS_NAMES.get(int(status[-1]), text[-1])
    assert text[-1] != "ok" and not text[-1].isdigit()
    assert np.all((text == "ok") == tab.ok)


def test_status_docstring_explains_every_code():
    doc = DesignTable.status.__doc__ + DesignTable.status_text.__doc__
    for code, name in protocol.STATUS_NAMES.items():
        assert f"{code} " in doc and name in doc, (code, name)
    assert "velocity" in doc and "acceleration" in doc      # the 10 + and 20 + codes
