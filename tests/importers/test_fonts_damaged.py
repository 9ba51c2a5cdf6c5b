"""Damaged fonts: each is built here from the shipped DejaVu Sans by patching its
bytes, and each is one line naming the file and what is wrong, exit 2, from ``aaeval import
text`` and from the ``freetype`` method; WOFF is read, WOFF2 is refused by name."""

from __future__ import annotations

import io
import struct

import pytest

from aaeval.cli import main


def _table_dir(data: bytes) -> dict:
    count = struct.unpack(">H", data[4:6])[0]
    entries = {}
    for i in range(count):
        tag, _, offset, length = struct.unpack(">4sIII", data[12 + 16 * i: 28 + 16 * i])
        entries[tag.decode()] = (12 + 16 * i, offset, length)
    return entries


def _patched_entry(data: bytes, tag: str, *, offset=None, length=None) -> bytes:
    out = bytearray(data)
    pos, o, n = _table_dir(data)[tag]
    struct.pack_into(">4sIII", out, pos, tag.encode(), 0, o if offset is None else offset, n if length is None else length)
    return bytes(out)


def _patched_field(data: bytes, tag: str, at: int, value: int) -> bytes:
    out = bytearray(data)
    struct.pack_into(">H", out, _table_dir(data)[tag][1] + at, value)
    return bytes(out)


def damaged_fonts() -> dict[str, tuple[bytes, str]]:
    """name -> (bytes, a word the error line must hold)."""
    from aaeval.importers.text import DEFAULT_FONT
    from aaeval.scenes.sources import font_path

    data = font_path(".", DEFAULT_FONT).read_bytes()
    return {
        "fewglyphs.ttf": (_patched_field(data, "maxp", 4, 30), "maxp"),  # numGlyphs 30 of 6000+
        "glyflength.ttf": (_patched_entry(data, "glyf", length=len(data) * 4), "glyf"),
        "glyfoffset.ttf": (_patched_entry(data, "glyf", offset=len(data) + 1000), "glyf"),
        "upem0.ttf": (_patched_field(data, "head", 18, 0), "unitsPerEm"),
        "font.woff2": (b"wOF2" + data[4:], "WOFF2"),
    }


FONTS = ["fewglyphs.ttf", "glyflength.ttf", "glyfoffset.ttf", "upem0.ttf", "font.woff2"]


@pytest.fixture(scope="module")
def fonts():
    return damaged_fonts()


def _one_line(capsys, argv, name, word=None):
    capsys.readouterr()
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert name in err, err
    if word:
        assert word in err, err
    return err


@pytest.mark.parametrize("name", FONTS)
def test_import_text_refuses_a_damaged_font_in_one_line(tmp_path, capsys, monkeypatch, fonts, name):
    monkeypatch.chdir(tmp_path)
    data, word = fonts[name]
    (tmp_path / name).write_bytes(data)
    _one_line(capsys, ["import", "text", "Hello 0123456789", "--font", name, "-o", "x.toml"], name, word)
    assert not (tmp_path / "x.toml").exists()


@pytest.mark.parametrize("name", FONTS)
def test_freetype_method_refuses_a_damaged_font_in_one_line(tmp_path, capsys, monkeypatch, fonts, name):
    monkeypatch.chdir(tmp_path)
    assert main(["import", "text", "Hi 01", "-o", "good.toml"]) == 0
    data, _ = fonts[name]
    (tmp_path / name).write_bytes(data)
    text = (tmp_path / "good.toml").read_text()
    assert 'font = "matplotlib:DejaVuSans.ttf"' in text
    (tmp_path / "bad.toml").write_text(text.replace('font = "matplotlib:DejaVuSans.ttf"', f'font = "{name}"'))
    _one_line(capsys, ["render", "bad.toml", "-m", "freetype", "-o", "o.png"], name)
    assert not (tmp_path / "o.png").exists()


def test_woff_is_read_by_the_importer_and_freetype(tmp_path, capsys, monkeypatch):
    """WOFF (zlib) is supported: the same glyphs as the TTF it was made from."""
    from fontTools.ttLib import TTFont

    from aaeval.importers.text import DEFAULT_FONT
    from aaeval.scenes.sources import font_path

    monkeypatch.chdir(tmp_path)
    font = TTFont(io.BytesIO(font_path(".", DEFAULT_FONT).read_bytes()))
    font.flavor = "woff"
    font.save(str(tmp_path / "f.woff"))
    assert main(["import", "text", "Hi 01", "--font", "f.woff", "-o", "w.toml"]) == 0
    assert main(["import", "text", "Hi 01", "-o", "t.toml"]) == 0
    woff = (tmp_path / "w.toml").read_text().replace('"f.woff"', '"matplotlib:DejaVuSans.ttf"')
    assert woff == (tmp_path / "t.toml").read_text()
    assert main(["render", "w.toml", "-m", "freetype", "-o", "o.png"]) == 0
