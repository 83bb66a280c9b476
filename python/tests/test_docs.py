"""The example of docs/python.md runs as written."""
import os
import re

from conftest import PROJECT_DIR


def test_python_md_example_runs(tmp_path, capsys, monkeypatch):
    text = open(os.path.join(PROJECT_DIR, "docs", "python.md")).read()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    exec(compile(blocks[0], "docs/python.md", "exec"), {})
    out = capsys.readouterr().out
    assert re.search(r"\(\d+, 3\) \(\d+, 8\)", out), out
    assert "error 4" in out and "no_such_file.obj" in out
    assert (tmp_path / "plate.exo").exists() and (tmp_path / "plate.vtu").exists()
    import json
    import mesohex
    report = json.loads((tmp_path / "plate.json").read_text())
    assert report["partition"]["parts"] == 2
    import meshio  # meshio writes compressed binary .vtu, which only meshio reads back
    written = meshio.read(str(tmp_path / "plate.vtu"))
    assert written.cells[0].data.shape == (report["quality"]["hexes"], 8)
    assert written.cell_data["partition"][0].max() == 1
