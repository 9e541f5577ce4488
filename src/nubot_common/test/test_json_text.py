"""The JSON the project writes is strict: a NaN or an infinity is null, and every reader takes the text."""

import json
import math

from nubot_common.json_text import strict_json


def test_non_finite_numbers_are_written_as_null_everywhere_in_the_data():
    data = {"interval": {"mean": 1.5, "low": math.nan, "high": math.inf}, "rates": [1.0, -math.inf, (2, math.nan)],
            "count": 3, "name": "NaN"}
    text = strict_json(data)
    assert "NaN" not in text.replace('"NaN"', "") and "Infinity" not in text and text.endswith("\n")
    assert json.loads(text, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c))) == {
        "interval": {"mean": 1.5, "low": None, "high": None}, "rates": [1.0, None, [2, None]], "count": 3,
        "name": "NaN"}
