"""ilocalg: the algorithms of the iLoc toolkit for smartphone indoor positioning research.

The package computes; it never draws (plots live in :mod:`ilocviz`) and importing it has no
side effects and does not import matplotlib.

Subpackages
-----------
``io``          loaders for real recordings and the schemas below
``sim``         the simulators that make the embedded default data (seeded, documented)
``wifi``        fingerprint estimators (Simplified-RADAR, Simplified-Horus, KNN)
``pdr``         step detection, step length, heading, dead reckoning
``fusion``      Kalman fusion of steps with Wi-Fi fixes, smoothers
``ins``         strapdown mechanisation and error-state EKFs
``optim``       particle swarm optimisation
``photo``       photo positioning from points of interest
``track``       a walk in, a track out: the PDR + Wi-Fi (+ map) pipeline of one walk, learned from others
``experiments`` each reproduced experiment as a function ``run(seed, fast, **params)``
``papers``      the papers' published values, set beside reproduced ones in comparison rows
``metrics``     positioning error statistics; ``units``: unit conversions
``workflow``    not algorithms: the reproduce runner, report files, sweeps, notebook pairs, the CLI

Data types
----------
Defined once here; the column-name constants live in :mod:`ilocalg.io.schema`.

Time
    Seconds as float64, named ``t_s``. Every time-indexed frame is strictly increasing in time.
IMU log
    ``DataFrame`` indexed by ``t_s`` with any subset of the columns ``acc_x_mps2``, ``acc_y_mps2``,
    ``acc_z_mps2`` (specific force, m/s^2), ``gyr_x_radps`` ... (angular rate, rad/s) and
    ``mag_x_ut`` ... (magnetic field, microtesla), all in the phone frame ``_p`` (below).
Wi-Fi scans
    Long ``DataFrame`` with columns ``t_s``, ``scan_id`` (int), ``bssid`` (str), ``rssi_dbm``
    (float) and optionally ``freq_mhz``; one row per access point heard in a scan.
Fingerprint set
    :class:`ilocalg.io.schema.FingerprintSet`: an RSSI matrix ``rssi_dbm`` of shape
    (n_samples, n_aps), float, ``NaN`` meaning "not heard"; the access point ids ``ap_ids``;
    positions ``x_m``, ``y_m`` and optionally ``floor`` and ``building`` per sample.
Ground-truth waypoints
    ``DataFrame`` with columns ``t_s``, ``x_m``, ``y_m`` and optionally ``floor``.
Pressure log
    ``DataFrame`` indexed by ``t_s`` with ``pressure_hpa`` (barometer, hPa).
Recording (one walk)
    :class:`ilocalg.io.Recording`, a frozen dataclass that every walk loader converts to
    (:func:`ilocalg.io.load_recording` picks the loader from the file's content;
    :func:`ilocalg.io.write_ipin_logfile` writes any recording, simulated walks included, as an IPIN
    logfile): ``imu`` (IMU log), ``wifi`` (Wi-Fi scans), ``pressure`` (pressure log or None),
    ``truth`` (ground-truth points ``t_s, x_m, y_m, floor``; ``floor`` NaN when unknown, plus
    ``lat_deg, lon_deg`` for geographic sources), ``frame`` (:class:`ilocalg.io.LocalFrame`: the
    local frame of ``truth``, for geographic sources an origin and a PROJ azimuthal equidistant
    projection, so walks of several files share one frame), ``step_t_s`` (true step times, when
    known) and ``meta`` (format, device, counts of skipped or policy-changed records). The track
    pipeline (:mod:`ilocalg.track`) takes recordings.
Trajectories / results
    ``DataFrame`` with ``x_m``, ``y_m`` (and ``t_s`` or ``step`` as the index); summaries are
    ``DataFrame`` objects or frozen dataclasses.

Frames and units
----------------
Positions are metres in a local, planar map frame ``(x_m, y_m)`` (x east, y north for the
simulated sets; the data set's own map frame for real sets). Headings ``theta_rad`` are measured
from the map x axis, counter-clockwise; compass yaw ``psi_rad`` from north, clockwise, is
converted explicitly by :func:`ilocalg.units.yaw_to_theta`. Three frames of three axes:

Phone frame ``_p``
    The phone's sensor frame, Android convention: x right, y up the screen (towards the top edge),
    z out of the screen. IMU logs, step detection and heading (:mod:`ilocalg.pdr`) use it.
Body frame ``_b``
    The inertial navigation body frame (:mod:`ilocalg.ins`): x forward, y left, z up. For a phone
    held flat in front of the walker, screen up, its top pointing along the walk,
    ``v_b = MAT_PHONE_TO_BODY @ v_p`` (:data:`ilocalg.ins.MAT_PHONE_TO_BODY`, a -90 deg rotation about
    z: ``x_b = y_p``, ``y_b = -x_p``, ``z_b = z_p``; :func:`ilocalg.ins.phone_to_body`).
Navigation frame ``_n``
    Local-level east-north-up, metres, fixed to the site; ``mat_nb`` rotates body to nav
    (``v_n = mat_nb @ v_b``).

Where code lives
----------------
- An algorithm lives in its algorithm package (``wifi``, ``pdr``, ``fusion``, ``ins``, ``optim``,
  ``photo``, ``track``), written against the data types above, never in ``experiments``. A pipeline a
  user runs outside any notebook (a walk in, a track out) is an algorithm module too
  (:mod:`ilocalg.track`, :mod:`ilocalg.ins.pipeline`).
- An experiment module (``ilocalg.experiments.<name>``) is thin: ``run(seed, fast, **params)`` simulates
  or loads, calls algorithm packages and returns its tables (with :mod:`ilocalg.papers` rows). It imports
  algorithm packages, ``sim`` and ``papers``, never another experiment. Parameter studies
  (``study_*``) also use the task plumbing of :mod:`ilocalg.workflow.studies`.
- Extension points have one registry each, inside their package: step detectors in
  :mod:`ilocalg.pdr.registry` (``@register_step_detector(name)``), Wi-Fi estimators in
  :mod:`ilocalg.wifi.registry` (``register_estimator``), INS measurement updates as objects of the
  :class:`ilocalg.ins.eskf.Measurement` protocol (innovation, H and R).
- The same maths is written once: a shared helper is public in its package, or private in one helper
  module of that package; no module imports another module's private names.
- :mod:`ilocalg.workflow` (runner, reports, sweeps, the command line) imports the rest, never the
  reverse; the ``evaluate`` commands call algorithm packages, never experiments.
- Papers are cited by author and year in each docstring's ``References`` section, with equation numbers.

Randomness
----------
Every stochastic function takes ``rng: numpy.random.Generator | int | None`` (see
:func:`ilocalg.units.as_rng`): the same seed gives the same bytes.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
