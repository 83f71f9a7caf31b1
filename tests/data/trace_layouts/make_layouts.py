#!/usr/bin/env python3
"""Small recordings in the exact column layouts of public eye-tracker exports, with synthetic
motion, for the `trace import --guess` tests (tests/trace/guess_search_test.cpp).

    python3 tests/data/trace_layouts/make_layouts.py [tuned|heldout|all]

Writes tuned/*.csv|tsv and heldout/*. The motion is the same model for every file (fovsim
axes: right-handed, +Y up, the head looks down -Z): the head turns +-30 deg in yaw and a few
degrees in pitch and roll, the eye makes fixations of 200-400 ms and saccades (duration
21 ms + 2.2 ms/deg, Carpenter 1988) within +-15 x +-10 deg of head forward, with 0.1 deg
noise and a 150 ms blink every ~3 s. Each writer converts it to its format's published
conventions (the docstring of each writer names the source). The held-out files were written
after the scorer in sim/trace/map_search.cpp was frozen and were not used to tune it.
Deterministic: a fixed seed per file.
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


# ---- motion -------------------------------------------------------------------------------

def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]]


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def quat_from_mat(m):
    """(w, x, y, z) of a proper rotation matrix."""
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        w, x, y, z = 0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        w, x, y, z = (m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s
    elif m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        w, x, y, z = (m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s
    else:
        s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
        w, x, y, z = (m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s
    if w < 0:
        w, x, y, z = -w, -x, -y, -z
    return w, x, y, z


def reflect(m, axes):
    """M R M^T for the diagonal reflection/permutation matrix `axes` (3x3)."""
    mt = [[axes[j][i] for j in range(3)] for i in range(3)]
    return mat_mul(mat_mul(axes, m), mt)


UNITY = [[1, 0, 0], [0, 1, 0], [0, 0, -1]]  # fovsim <-> Unity (z flips)


class Sample:
    pass


def motion(n, hz, seed, t0=0.0):
    rnd = random.Random(seed)
    out = []
    az, el = 0.0, 0.0
    src, dst = (0.0, 0.0), (0.0, 0.0)
    sac_start, sac_dur = -1.0, 0.0
    next_sac = 0.3
    for i in range(n):
        t = i / hz
        if t >= next_sac and sac_start < 0:
            src = (az, el)
            dst = (rnd.uniform(-15, 15), rnd.uniform(-10, 10))
            amp = math.hypot(dst[0] - src[0], dst[1] - src[1])
            sac_start, sac_dur = t, (21 + 2.2 * amp) / 1000
        if sac_start >= 0:
            u = min(1.0, (t - sac_start) / sac_dur)
            f = 0.5 - 0.5 * math.cos(math.pi * u)
            az, el = src[0] + f * (dst[0] - src[0]), src[1] + f * (dst[1] - src[1])
            if u >= 1:
                sac_start = -1
                next_sac = t + rnd.uniform(0.2, 0.4)
        s = Sample()
        s.t = t0 + t
        yaw = math.radians(30 * math.sin(2 * math.pi * 0.15 * t))
        pitch = math.radians(-5 + 5 * math.sin(2 * math.pi * 0.1 * t))
        roll = math.radians(2 * math.sin(2 * math.pi * 0.2 * t))
        s.R = mat_mul(rot_y(yaw), mat_mul(rot_x(pitch), rot_z(roll)))  # world-from-head
        s.pos = [0.1 * math.sin(0.5 * t), 1.6 + 0.02 * math.sin(3 * t), -0.05 * t]
        a = math.radians(az + rnd.gauss(0, 0.1))
        e = math.radians(el + rnd.gauss(0, 0.1))
        s.az, s.el = math.degrees(a), math.degrees(e)
        s.gaze = [math.cos(e) * math.sin(a), math.sin(e), -math.cos(e) * math.cos(a)]  # head
        s.world = mat_vec(s.R, s.gaze)
        s.valid = i % 97 != 50
        out.append(s)
    # Blinks: 150 ms every ~3 s (on top of the odd lost sample).
    period = int(3 * hz)
    for i in range(n):
        if i % period >= period - int(0.15 * hz):
            out[i].valid = False
    return out


def f(v, d=6):
    return f"{v:.{d}f}"


def write(path, header, rows, sep):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as fh:
        fh.write(sep.join(header) + "\n")
        for r in rows:
            fh.write(sep.join(r) + "\n")


# ---- tuned layouts ------------------------------------------------------------------------

def pupil_core(path):
    """Pupil Labs Core, Pupil Player raw-data export gaze_positions.csv (docs.pupil-labs.com,
    "Raw Data Exporter"): gaze_timestamp in s of Pupil time, world_index, confidence 0..1
    (below 0.6 is unreliable), norm_pos_x/y (0..1, origin bottom-left), base_data,
    gaze_point_3d_x/y/z (mm) and per-eye eye_center/gaze_normal in the world camera's 3D frame
    (OpenCV: x right, y down, z forward). No head pose. 200 Hz binocular."""
    hz = 200
    header = ["gaze_timestamp", "world_index", "confidence", "norm_pos_x", "norm_pos_y",
              "base_data", "gaze_point_3d_x", "gaze_point_3d_y", "gaze_point_3d_z",
              "eye_center0_3d_x", "eye_center0_3d_y", "eye_center0_3d_z",
              "gaze_normal0_x", "gaze_normal0_y", "gaze_normal0_z",
              "eye_center1_3d_x", "eye_center1_3d_y", "eye_center1_3d_z",
              "gaze_normal1_x", "gaze_normal1_y", "gaze_normal1_z"]
    rows = []
    rnd = random.Random(11)
    for i, s in enumerate(motion(400, hz, 1, t0=5873.2041)):
        g = s.gaze
        cv = [g[0], -g[1], -g[2]]  # OpenCV axes
        conf = rnd.uniform(0.85, 1.0) if s.valid else rnd.uniform(0.0, 0.3)
        if not s.valid:
            cv = [rnd.uniform(-1, 1), rnd.uniform(-1, 1), rnd.uniform(-1, 1)]
            nrm = math.sqrt(sum(c * c for c in cv))
            cv = [c / nrm for c in cv]
        u = 0.5 + 0.5 * cv[0] / max(0.3, cv[2]) if cv[2] > 0 else 0.5
        v = 0.5 - 0.5 * cv[1] / max(0.3, cv[2]) if cv[2] > 0 else 0.5
        p3 = [500 * c for c in cv]
        ts = f"{s.t:.6f}"
        rows.append([ts, str(i // 7), f(conf, 4), f(u), f(v), f"{ts}-0 {ts}-1"] +
                    [f(c, 4) for c in p3] +
                    [f(-32.1, 3), f(14.0, 3), f(-18.5, 3)] + [f(c) for c in cv] +
                    [f(30.4, 3), f(13.2, 3), f(-17.9, 3)] + [f(c) for c in cv])
    write(path, header, rows, ",")


def sranipal_unity(path):
    """HTC VIVE Pro Eye through SRanipal in Unity, one row per ViveSR.anipal.Eye.EyeData_v2
    callback: timestamp (ms) and frame_sequence, per eye SingleEyeData's
    eye_data_validata_bit_mask (bits: 0 gaze origin, 1 gaze direction, 2 pupil diameter,
    3 eye openness, 4 pupil position; 31 when all valid), gaze_origin_mm and
    gaze_direction_normalized in SRanipal's right-handed eye frame (+x to the user's left, +y
    up, +z forward), eye_openness; the head is Unity's Camera.main transform (left-handed, +Z
    forward), rotation as x, y, z, w. Blinks: direction bit cleared, direction (0, 0, 0)."""
    hz = 120
    header = ["timestamp", "frame_sequence"]
    for e in ("left", "right"):
        header += [f"{e}.eye_data_validata_bit_mask", f"{e}.gaze_origin_mm.x",
                   f"{e}.gaze_origin_mm.y", f"{e}.gaze_origin_mm.z",
                   f"{e}.gaze_direction_normalized.x", f"{e}.gaze_direction_normalized.y",
                   f"{e}.gaze_direction_normalized.z", f"{e}.eye_openness"]
    header += ["Camera.position.x", "Camera.position.y", "Camera.position.z",
               "Camera.rotation.x", "Camera.rotation.y", "Camera.rotation.z", "Camera.rotation.w"]
    rows = []
    for i, s in enumerate(motion(360, hz, 2)):
        g = s.gaze
        src = [-g[0], g[1], -g[2]]  # SRanipal eye frame
        row = [str(1200345 + int(round(s.t * 1000))), str(88000 + i)]
        for side, ox in (("left", 32.0), ("right", -32.0)):
            lost_one = (i % 53 == 20 and side == "left")
            if s.valid and not lost_one:
                row += ["31", f(ox, 3), "4.1", "-38.0"] + [f(c) for c in src] + ["1.0"]
            else:
                row += ["8", "0", "0", "0", "0", "0", "0", "0.05"]
        Ru = reflect(s.R, UNITY)
        w, x, y, z = quat_from_mat(Ru)
        pu = [s.pos[0], s.pos[1], -s.pos[2]]
        row += [f(c) for c in pu] + [f(x), f(y), f(z), f(w)]
        rows.append(row)
    write(path, header, rows, ",")


def tobii_pro_lab(path):
    """Tobii Pro Glasses 2 recording exported by Tobii Pro Lab (Data Export, tab-separated):
    Recording timestamp in microseconds, Sensor ("Eye Tracker" rows interleaved with
    "Gyroscope" rows that carry no gaze), Gaze point X/Y (scene-video pixels), Gaze point 3D
    X/Y/Z (mm), per-eye Gaze direction left/right X/Y/Z in the glasses' frame (+X to the
    wearer's left, +Y up, +Z forward), Pupil diameter left/right (mm), Validity left/right
    ("Valid"/"Invalid"), Eye movement type, Gyro X/Y/Z (deg/s). No head pose. 100 Hz."""
    hz = 100
    header = ["Recording timestamp [\u03bcs]", "Sensor", "Participant name", "Gaze point X",
              "Gaze point Y", "Gaze point 3D X", "Gaze point 3D Y", "Gaze point 3D Z",
              "Gaze direction left X", "Gaze direction left Y", "Gaze direction left Z",
              "Gaze direction right X", "Gaze direction right Y", "Gaze direction right Z",
              "Pupil diameter left", "Pupil diameter right", "Validity left", "Validity right",
              "Eye movement type", "Gyro X", "Gyro Y", "Gyro Z"]
    rows = []
    for i, s in enumerate(motion(300, hz, 3)):
        g = s.gaze
        src = [-g[0], g[1], -g[2]]
        ts = int(round(s.t * 1e6)) + 81234567
        if s.valid:
            gp = [f"{960 + 900 * g[0]:.0f}", f"{540 - 900 * g[1]:.0f}"]
            d = [f(c) for c in src]
            rows.append([str(ts), "Eye Tracker", "P01"] + gp + [f(600 * c, 2) for c in src] +
                        d + d + ["3.21", "3.18", "Valid", "Valid", "Fixation", "", "", ""])
        else:
            rows.append([str(ts), "Eye Tracker", "P01", "", "", "", "", ""] + [""] * 6 +
                        ["", "", "Invalid", "Invalid", "EyesNotFound", "", "", ""])
        if i % 5 == 2:
            rows.append([str(ts + 3000), "Gyroscope", "P01"] + [""] * 15 +
                        ["Unclassified", "1.25", "-0.50", "0.75"])
    write(path, header, rows, "\t")


TUNED = {"pupil_core_gaze_positions.csv": pupil_core,
         "sranipal_unity.csv": sranipal_unity,
         "tobii_pro_lab_glasses2.tsv": tobii_pro_lab}

# ---- held-out layouts (written after the scorer was frozen; not used to tune it) -----------

def varjo_base_log(path):
    """Varjo XR-3 / Aero, Varjo Base eye-tracking data logging (CSV): raw_timestamp (ns),
    frame_number, status (0 invalid, 1 adjusting, 2 valid), combined gaze_forward and
    gaze_origin in the HMD frame with +Z forward, per-eye left_/right_ status and forward,
    pupil sizes, ipd; the HMD pose in Varjo's world frame (right-handed, +Y up, -Z forward),
    rotation w, x, y, z. 200 Hz. Lost samples: status 0 and a (0, 0, 0) forward."""
    hz = 200
    header = ["raw_timestamp", "log_time", "frame_number", "status", "gaze_forward_x",
              "gaze_forward_y", "gaze_forward_z", "gaze_origin_x", "gaze_origin_y",
              "gaze_origin_z", "left_status", "left_forward_x", "left_forward_y",
              "left_forward_z", "right_status", "right_forward_x", "right_forward_y",
              "right_forward_z", "left_pupil_size", "right_pupil_size", "ipd",
              "HMD_position_x", "HMD_position_y", "HMD_position_z", "HMD_rotation_w",
              "HMD_rotation_x", "HMD_rotation_y", "HMD_rotation_z"]
    rows = []
    for i, s in enumerate(motion(400, hz, 4)):
        g = s.gaze
        src = [g[0], g[1], -g[2]]
        ts = 1686570000123456789 + int(round(s.t * 1e9))
        w, x, y, z = quat_from_mat(s.R)
        head = [f(c) for c in s.pos] + [f(w), f(x), f(y), f(z)]
        if s.valid:
            d = [f(c) for c in src]
            rows.append([str(ts), f"{s.t:.4f}", str(1000 + i // 2), "2"] + d +
                        ["0.0", "0.0", "0.0", "2"] + d + ["2"] + d + ["3.1", "3.2", "63.5"] + head)
        else:
            z3 = ["0", "0", "0"]
            rows.append([str(ts), f"{s.t:.4f}", str(1000 + i // 2), "0"] + z3 + z3 + ["0"] + z3 +
                        ["0"] + z3 + ["0", "0", "63.5"] + head)
    write(path, header, rows, ",")


def quest_pro_ovreyegaze(path):
    """Meta Quest Pro in Unity (Meta XR SDK), one row per frame from a logger of OVREyeGaze
    components in world-space tracking mode: Time.time (s), the centre-eye camera
    transform (Unity: left-handed, +Y up, +Z forward; rotation x, y, z, w), each eye's
    transform.rotation (world space; the gaze is its +Z axis) and OVREyeGaze.Confidence
    (0..1, the SDK's default threshold 0.5). 72 Hz."""
    hz = 72
    header = ["time", "head_pos_x", "head_pos_y", "head_pos_z", "head_rot_x", "head_rot_y",
              "head_rot_z", "head_rot_w"]
    for e in ("left", "right"):
        header += [f"{e}_eye_rot_x", f"{e}_eye_rot_y", f"{e}_eye_rot_z", f"{e}_eye_rot_w",
                   f"{e}_eye_confidence"]
    rows = []
    rnd = random.Random(5)
    for s in motion(360, hz, 5):
        Ru = reflect(s.R, UNITY)
        hw, hx, hy, hz_ = quat_from_mat(Ru)
        wg = s.world  # fovsim world gaze
        # Eye rotation: yaw/pitch taking Unity +Z to the Unity world gaze (no roll).
        gu = [wg[0], wg[1], -wg[2]]
        yaw = math.atan2(gu[0], gu[2])
        pitch = -math.asin(max(-1.0, min(1.0, gu[1])))
        Re = mat_mul(rot_y(yaw), rot_x(pitch))
        ew, ex, ey, ez = quat_from_mat(Re)
        row = [f"{s.t:.5f}", f(s.pos[0]), f(s.pos[1]), f(-s.pos[2]), f(hx), f(hy), f(hz_), f(hw)]
        for _ in ("left", "right"):
            if s.valid:
                row += [f(ex), f(ey), f(ez), f(ew), f(rnd.uniform(0.8, 1.0), 3)]
            else:
                row += ["0", "0", "0", "1", f(rnd.uniform(0.0, 0.2), 3)]
        rows.append(row)
    write(path, header, rows, ",")


def gazebase(path):
    """GazeBase (Griffith et al. 2021), one CSV per recording from an EyeLink 1000 at 1000 Hz:
    n (ms), x and y (gaze in degrees of visual angle from the screen centre, +y up), val
    (0 valid, non-zero: sample invalid), xT and yT (the target, deg), lab (the task's
    label column). Invalid samples have NaN gaze. Desktop: no head pose."""
    hz = 1000
    header = ["n", "x", "y", "val", "xT", "yT", "lab"]
    rows = []
    for i, s in enumerate(motion(800, hz, 6)):
        t = str(int(round(s.t * 1000)) + 8)
        if s.valid:
            rows.append([t, f(s.az, 4), f(s.el, 4), "0", "0.0", "0.0", "1"])
        else:
            rows.append([t, "NaN", "NaN", "4", "0.0", "0.0", "1"])
    write(path, header, rows, ",")


HELDOUT = {"varjo_base_gaze_log.csv": varjo_base_log,
           "quest_pro_ovreyegaze_unity.csv": quest_pro_ovreyegaze,
           "gazebase_s1.csv": gazebase}


# ---- second held-out set (written after the search was frozen again at 69c9a56) -------------

def unity_euler(R):
    """Unity Transform.eulerAngles (deg, 0..360) of a fovsim world-from-head matrix."""
    Ru = reflect(R, UNITY)  # R = Ry Rx Rz in Unity's axes
    x = math.asin(max(-1.0, min(1.0, -Ru[1][2])))
    y = math.atan2(Ru[0][2], Ru[2][2])
    z = math.atan2(Ru[1][0], Ru[1][1])
    return [math.degrees(a) % 360 for a in (x, y, z)]


def tobii_xr_unity(path):
    """Tobii XR SDK in Unity (TobiiXR.GetEyeTrackingData(TobiiXR_TrackingSpace.World)), one row
    per frame: Timestamp (s, Time.unscaledTime), GazeRay.Origin/Direction in Unity world axes
    (left-handed, +Z forward), GazeRay.IsValid, IsLeftEyeBlinking/IsRightEyeBlinking,
    ConvergenceDistance(IsValid); the head from Camera.main.transform: position and
    eulerAngles (degrees, 0..360, applied Z, X, Y). 90 Hz."""
    hz = 90
    header = ["Timestamp", "GazeRay.Origin.x", "GazeRay.Origin.y", "GazeRay.Origin.z",
              "GazeRay.Direction.x", "GazeRay.Direction.y", "GazeRay.Direction.z",
              "GazeRay.IsValid", "IsLeftEyeBlinking", "IsRightEyeBlinking",
              "ConvergenceDistance", "ConvergenceDistanceIsValid", "HeadPosition.x",
              "HeadPosition.y", "HeadPosition.z", "HeadEulerAngles.x", "HeadEulerAngles.y",
              "HeadEulerAngles.z"]
    rows = []
    for s in motion(360, hz, 7, t0=12.5):
        pu = [s.pos[0], s.pos[1], -s.pos[2]]
        wu = [s.world[0], s.world[1], -s.world[2]]
        e = unity_euler(s.R)
        if s.valid:
            g = [f(c) for c in wu] + ["True", "False", "False", "1.2", "True"]
        else:
            g = ["0", "0", "0", "False", "True", "True", "0", "False"]
        rows.append([f"{s.t:.5f}"] + [f(c) for c in pu] + g + [f(c) for c in pu] +
                    [f(c, 4) for c in e])
    write(path, header, rows, ",")


def pupil_cloud_gaze(path):
    """Pupil Labs Neon / Invisible, Pupil Cloud "Timeseries Data" gaze.csv: section id,
    recording id, timestamp [ns] (epoch), gaze x/y [px] in the scene camera image, worn
    (1 or 0), fixation id, blink id (empty outside blinks), azimuth [deg] and elevation [deg]
    (the gaze in the scene camera: azimuth positive right, elevation positive up). 200 Hz."""
    hz = 200
    header = ["section id", "recording id", "timestamp [ns]", "gaze x [px]", "gaze y [px]",
              "worn", "fixation id", "blink id", "azimuth [deg]", "elevation [deg]"]
    rows = []
    blink = 0
    for i, s in enumerate(motion(400, hz, 8)):
        ts = 1700000000000000000 + int(round(s.t * 1e9))
        bid = ""
        if not s.valid:
            blink += 1 if i == 0 or rows[-1][7] == "" else 0
            bid = str(blink)
        rows.append(["a1b2c3", "d4e5f6", str(ts), f(800 + 20 * s.az, 3), f(600 - 20 * s.el, 3),
                     "1", "" if bid else str(i // 60 + 1), bid, f(s.az, 4), f(s.el, 4)])
    write(path, header, rows, ",")


HELDOUT2 = {"tobii_xr_unity_world.csv": tobii_xr_unity,
            "pupil_cloud_gaze.csv": pupil_cloud_gaze}


def main():
    which = sys.argv[1] if len(sys.argv) > 1 else "all"
    sets = {"tuned": TUNED, "heldout": {**HELDOUT, **HELDOUT2}}
    for name, files in sets.items():
        if which not in (name, "all"):
            continue
        for fname, fn in files.items():
            fn(os.path.join(HERE, name, fname))


if __name__ == "__main__":
    main()
