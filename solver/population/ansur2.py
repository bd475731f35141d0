"""ANSUR II (U.S. Army, 2012) by sex: stature (m) and body mass (kg) with their correlation, and the extra body
measurements (m) as linear regressions on stature and mass with correlated residuals.

Source: Gordon C.C., Blackwell C.L., Bradtmiller B., et al. (2014), "2012 Anthropometric Survey of U.S. Army
Personnel: Methods and Summary Statistics", Technical Report NATICK/TR-15/007, U.S. Army Natick Soldier RD&E
Center; its public working databases "ANSUR II MALE Public.csv" (4082 men) and "ANSUR II FEMALE Public.csv"
(1986 women), one row per subject, lengths in mm, ``weightkg`` in tenths of kg.

How the numbers were obtained (verified, but computed by us, not transcribed): read from two independent public
GitHub copies of the databases whose measurement values agree row by row (coleharlow12/ANSURDataAnalysis,
sha256 of the CSVs as stored there 2c10580d... men, ed7e800a... women; KhadijehValipour/ANSUR), then
unweighted sample means, standard deviations (n - 1) and Pearson correlations, and ordinary least squares of each
extra measurement on (1, stature, mass) with the residual standard deviation (n - 3) and the residuals'
correlations. The report's own summary tables are weighted to the Army's demographics and were NOT checked
against these numbers; the sample is soldiers aged 17-58 (mean age 30 men, 29 women), not a civilian workforce.

Survey variable per key: stature -> ``stature``, mass -> ``weightkg``, sitting_height -> ``sittingheight``,
shoulder_breadth -> ``biacromialbreadth``, upper_arm_length -> ``acromionradialelength``, forearm_length ->
``radialestylionlength``, hip_breadth -> ``hipbreadth``, foot_length -> ``footlength``.
"""

from __future__ import annotations

SOURCE = "ANSUR II public data (Gordon et al. 2014, NATICK/TR-15/007), unweighted statistics computed by us"

# Per sex: subjects, (mean, SD) of stature (m) and of body mass (kg), their Pearson correlation.
# fmt: off
STATS: dict[str, dict] = {
    "male": dict(n=4082, stature=(1.7562, 0.0686), mass=(85.52, 14.22), r=0.469),
    "female": dict(n=1986, stature=(1.6285, 0.0642), mass=(67.76, 10.98), r=0.533),
}

# Extra measurements: (intercept m, per m of stature, per kg of mass m/kg, residual SD m):
# value = intercept + b_stature * stature + b_mass * mass + residual.
EXTRAS = ("sitting_height", "shoulder_breadth", "upper_arm_length", "forearm_length", "hip_breadth", "foot_length")
REGRESSION: dict[str, dict[str, tuple[float, float, float, float]]] = {
    "male": {
        "sitting_height":   (0.2167, 0.3933, 0.000128, 0.0223),
        "shoulder_breadth": (0.2046, 0.0917, 0.000586, 0.0145),
        "upper_arm_length": (-0.0146, 0.1955, 0.000075, 0.0106),
        "forearm_length":   (-0.0130, 0.1591, 0.000016, 0.0108),
        "hip_breadth":      (0.2326, -0.0065, 0.001456, 0.0128),
        "foot_length":      (0.0449, 0.1204, 0.000173, 0.0089),
    },
    "female": {
        "sitting_height":   (0.2153, 0.3940, -0.000006, 0.0213),
        "shoulder_breadth": (0.1320, 0.1283, 0.000361, 0.0147),
        "upper_arm_length": (-0.0185, 0.1945, 0.000191, 0.0103),
        "forearm_length":   (-0.0149, 0.1525, 0.000118, 0.0110),
        "hip_breadth":      (0.2624, -0.0316, 0.002108, 0.0149),
        "foot_length":      (0.0379, 0.1180, 0.000239, 0.0083),
    },
}

# Correlations of the regression residuals, lower triangle in the order of EXTRAS (row i: columns 0..i-1).
RESIDUAL_CORRELATION: dict[str, tuple[tuple[float, ...], ...]] = {
    "male": (
        (0.001,),
        (-0.392, 0.060),
        (-0.535, 0.120, 0.355),
        (0.195, -0.051, -0.053, -0.108),
        (-0.258, 0.141, 0.105, 0.325, -0.069),
    ),
    "female": (
        (-0.010,),
        (-0.401, 0.010),
        (-0.557, 0.159, 0.310),
        (0.243, -0.117, -0.053, -0.234),
        (-0.309, 0.152, 0.128, 0.372, -0.187),
    ),
}
# fmt: on
