"""The job's HTML report: each method's own detail tables and plot through one code path (a new method needs no
change to html.py), and a side + front picture of every frame driving a verdict, with the lever arms drawn."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from solver.job.base import Method, lever, verdict
from solver.job.html import html_report
from solver.job.picture import body_segments, lever_segments
from solver.job.registry import METHODS
from solver.sketch import project


def _section(html: str, name: str) -> str:
    """The HTML of one method's section (its <h2 id=...> to the next <h2>)."""
    start = html.index(f'<h2 id="{name}">')
    return html[start : html.index("<h2", start + 1)]


def test_every_method_shows_its_detail_tables_and_plot(example: tuple[dict, Path]) -> None:
    report, out = example
    html = (out / "job.html").read_text()
    for name, method in METHODS.items():
        section = _section(html, name)
        for heading, _, rows in method.detail(report["methods"][name]):
            assert f"<h3>{heading}</h3>" in section and rows, (name, heading)
        assert f'alt="{report["methods"][name]["plot"]["title"]}"' in section, name


def test_the_shoulder_tool_has_its_per_shoulder_table_and_plot(example: tuple[dict, Path]) -> None:
    report, out = example
    section = _section((out / "job.html").read_text(), "shoulder_tool")
    for column in ("lever arm (m)", "load share (N)", "peak moment (N*m)", "damage per cycle", "CD", "P(clinic visit)"):
        assert f"<th>{column}</th>" in section, column
    shoulders = report["methods"]["shoulder_tool"]["shoulders"]
    assert set(shoulders) == {"r", "l"}  # both hands hold the box
    rows = re.findall(r"<tr><td>(right|left)</td><td>([0-9.]+)</td><td>([0-9.]+)</td>", section)
    assert {r[0] for r in rows} == {"right", "left"}
    for side, lever_arm, load in rows:
        s = shoulders[side[0]]
        assert abs(float(lever_arm) - s["lever_arm_m"]) < 0.01 and abs(float(load) - s["load_N"]) < 0.1
        assert 0.0 < s["probability_clinic_visit"] < 1.0
    assert abs(2 * s["load_N"] - 10.0 * 9.81) < 0.1  # 10 kg shared by the two hands
    assert "data:image/png;base64," in section.split("</table>")[-1]  # the plot after the tables


def test_each_driving_frame_has_a_picture_with_its_lever_arms(example: tuple[dict, Path]) -> None:
    report, out = example
    html = (out / "job.html").read_text()
    expected = 0
    for name, result in report["methods"].items():
        section = _section(html, name)
        title = METHODS[name].title
        for number in result["verdict"]["frames"]:
            captions = re.findall(rf"<figcaption><small>{re.escape(title)}: frame {number}\b[^<]*", section)
            assert len(captions) == 1, (name, number)
            for lv in result.get("levers", []):
                if lv["frame"] == number:
                    assert f"{lv['label']} {lv['length_m']:.2f} m" in captions[0]
            expected += 1
    assert expected >= 3  # LiFFT, the sequence, The Shoulder Tool each drive at least one frame
    assert html.count("<figure><img") == expected
    plots = sum(1 for r in report["methods"].values() if r.get("plot"))
    assert html.count("data:image/png;base64,") == expected + plots
    lifft = report["methods"]["lifft"]
    (lv,) = lifft["levers"]
    assert lv["frame"] == lifft["peak_frame"] and abs(lv["length_m"] - lifft["horizontal_distance_m"]) < 1e-9


def test_the_picture_draws_the_body_and_the_horizontal_lever(example: tuple[dict, Path]) -> None:
    from solver.io.result.read import read_result

    frame = read_result(example[1] / "motion.json").frames[-1]
    bones = body_segments(frame)
    assert len(bones) > 30
    assert all(np.linalg.norm(a) > 0.05 for a, _ in bones)  # no bone from the world origin (root translations)
    lv = example[0]["methods"]["lifft"]["levers"][0]
    flat, drop, _ = lever_segments(lv, np.array([0.0, 0.0, -1.0]))
    assert abs(np.linalg.norm(flat[1] - flat[0]) - lv["length_m"]) < 1e-9 and abs(flat[1][2] - flat[0][2]) < 1e-12
    assert np.allclose(drop[1], lv["end"])
    # the side view puts forward (-y) to the right, the front view the manikin's left (+x)
    assert np.allclose(project([[0.1, -0.2, 1.0]], "side"), [[0.2, 1.0]])
    assert np.allclose(project([[0.1, -0.2, 1.0]], "front"), [[0.1, 1.0]])


class _Grip(Method):
    """A method html.py has never heard of."""

    name, title, source = "grip_test", "Grip test method", "a test"

    def evaluate(self, inputs):  # pragma: no cover - only its result is used
        raise NotImplementedError

    def detail(self, result: dict) -> list:
        return [("grip forces", ["hand", "force (N)"], [["right", 12.5]])]


def test_a_new_method_needs_no_change_to_the_html(
    example: tuple[dict, Path], monkeypatch, tmp_path: Path, pictures_left_out
) -> None:
    from solver.io.result.read import read_result

    report, out = example
    frames = read_result(out / "motion.json").frames
    n = len(report["frames"])
    last = report["frames"][-1]
    result = dict(verdict=verdict("grip fine", 0, [last]), per_frame={"grip_N": [1.0] * n},
                  plot=dict(kind="line", y=["grip_N"], label="N", marks=[n - 1], title="grip over time"),
                  levers=[lever(last, [0.0, 0.0, 1.0], [0.0, -0.4, 0.9], 0.4, "grip lever")])  # fmt: skip
    monkeypatch.setitem(METHODS, "grip_test", _Grip())
    with pictures_left_out(keep=_Grip.title):  # the known methods' pictures: test_each_driving_frame_has_a_picture...
        html = html_report(report | {"methods": report["methods"] | {"grip_test": result}}, frames)
    section = _section(html, "grip_test")
    assert "<h3>grip forces</h3>" in section and "<td>12.5</td>" in section
    assert 'alt="grip over time"' in section
    assert f"Grip test method: frame {last} (grip lever 0.40 m)" in section
