"""Write ``docs/study_format.md`` from the format's table (``polyell.studies.file_format``)."""

from pathlib import Path

from polyell.studies.file_format import reference_page

if __name__ == "__main__":
    target = Path(__file__).with_suffix(".md")
    target.write_text(reference_page())
    print("regenerated", target)
