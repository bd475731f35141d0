"""The manifest's wheels: every platform gets the same packages at the same versions, one wheel each, and the test
environment (requirements.txt) runs the scipy and matplotlib that the extension ships."""

from __future__ import annotations

import tomllib
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))


def _platform(tag: str) -> str:
    """The Blender platform of a wheel's platform tag, as the build tool maps them ("any" for pure Python)."""
    if tag == "any":
        return "any"
    if tag.startswith("macosx"):
        return "macos-arm64" if tag.endswith("arm64") else "macos-x64"
    return "windows-x64" if tag == "win_amd64" else "linux-x64"


def test_every_platform_gets_one_wheel_of_each_compiled_package() -> None:
    by_platform: dict[str, dict[str, str]] = defaultdict(dict)
    for wheel in MANIFEST["wheels"]:
        name, version, *_, tag = Path(wheel).stem.split("-")
        platform = _platform(tag.split(".")[0])
        assert name not in by_platform[platform], f"two {name} wheels for {platform}"
        by_platform[platform][name] = version
    pure = by_platform.pop("any")
    assert set(by_platform) == set(MANIFEST["platforms"])
    first = next(iter(by_platform.values()))
    assert all(packages == first for packages in by_platform.values()), by_platform
    assert {"scipy", "matplotlib"} <= set(first) and not set(first) & set(pure)
    assert all(w.startswith("./wheels/") for w in MANIFEST["wheels"])


def test_the_tests_run_the_shipped_scipy_and_matplotlib() -> None:
    shipped = {Path(w).name.split("-")[0]: Path(w).name.split("-")[1] for w in MANIFEST["wheels"]}
    pins = {}
    for line in (ROOT / "requirements.txt").read_text(encoding="utf-8").splitlines():
        requirement = line.split("#")[0].strip()
        if "==" in requirement:
            name, version = requirement.split("==")
            pins[name.strip()] = version.strip()
    for name in ("scipy", "matplotlib", "pyparsing"):
        assert pins[name] == shipped[name], name
