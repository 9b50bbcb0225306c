"""Write ``docs/study_format.md`` and the JSON Schemas from ``polyell.studies.models``."""

import json
from pathlib import Path

from polyell.studies.models import json_schema, reference_page

if __name__ == "__main__":
    here = Path(__file__).parent
    (here / "study_format.md").write_text(reference_page())
    for kind in ("study", "robot"):
        (here / f"{kind}.schema.json").write_text(json.dumps(json_schema(kind), indent=2) + "\n")
    print("regenerated", here / "study_format.md", "and the JSON Schemas")
