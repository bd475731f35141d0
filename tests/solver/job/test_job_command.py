"""``manikin job``: the example job (its motion solved) and short stored motions give job.json, job.csv and a
one-file HTML report with each method's verdict on top."""

from __future__ import annotations

import csv
import json
from pathlib import Path


def test_the_example_job_writes_json_csv_and_an_offline_html_report(example: tuple[dict, Path]) -> None:
    report, out = example
    assert sorted(p.name for p in out.iterdir()) == ["job.csv", "job.html", "job.json", "motion.json"]
    data = json.loads((out / "job.json").read_text())
    assert list(data["verdicts"]) == ["lifft", "sequence", "shoulder_tool", "capable", "eaws"]
    lifft = data["methods"]["lifft"]
    assert lifft["lifts_per_shift"] == 800 and 0 < lifft["probability_high_risk"] < 1
    assert lifft["peak_load_moment_Nm"] == max(lifft["per_frame"]["lifft_load_moment_Nm"])
    assert 30 < lifft["peak_load_moment_Nm"] < 150  # 98 N at 0.3-1.5 m from L5/S1
    rows = list(csv.DictReader((out / "job.csv").open()))
    assert len(rows) == 60 and rows[0]["rula_action_level"] in "1234"
    html = (out / "job.html").read_text()
    assert html.index("Verdicts") < html.index("LiFFT low-back") < html.index("<h2>The job")
    pictures = sum(len(v["frames"]) for v in data["verdicts"].values())
    plots = sum(1 for r in data["methods"].values() if r.get("plot"))
    assert plots == 5 and html.count("data:image/png;base64,") == plots + pictures  # plots, pictures
    assert "<link" not in html and "<script" not in html and 'src="http' not in html  # nothing fetched: offline
    seq = data["methods"]["sequence"]
    assert sum(r["frames"] for r in seq["rula"]["levels"]) == 60
    assert abs(sum(r["seconds"] for r in seq["owas"]["levels"]) - 2.5) < 1e-9


def test_a_one_frame_motion_and_zero_repetitions(one_frame: tuple[dict, str]) -> None:
    data, printed = one_frame
    lifft = data["methods"]["lifft"]
    assert lifft["cumulative_damage"] == 0.0 and lifft["probability_high_risk"] == 0.0
    assert data["motion_time_s"] == 1 / 24 and data["frames"] == [30]
    assert all(v["frames"] == [30] for v in data["verdicts"].values())
    assert "LiFFT" in printed
