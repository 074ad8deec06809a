"""The toolkit's candidate configurations for UJIIndoorLoc-style fingerprinting, and its headline estimator.

The grids the cross-validations of :mod:`ilocalg.wifi.model_selection` choose among (offset-search ranges,
ensemble member sets, spot-averaged members, neighbour-weight exponents, the headline candidates), and
:func:`toolkit_estimator`, the headline configuration as one scikit-learn estimator (``python -m ilocalg evaluate
wifi --method toolkit``). Unfitted estimators only: nothing here scores or chooses (that is
:mod:`ilocalg.wifi.model_selection`), so the estimator registry can build the headline without importing the
model selection.

The representations and the Sorensen distance follow Torres-Sospedra et al. (2015), the offset search Tsui et al.
(2009); full references in :mod:`ilocalg.wifi.offset` and :mod:`ilocalg.wifi.model_selection`.
"""

from __future__ import annotations

__all__ = [
    "offset_shifts_db",
    "offset_grid",
    "ensemble_members",
    "ensemble_grid",
    "offset_range_grid",
    "SPOT_WEIGHT_POWERS",
    "SPOT_NEIGHBORS",
    "spot_grid",
    "HEADLINE_NEIGHBORS",
    "rank_member",
    "headline_grid",
    "TOOLKIT_HEADLINE",
    "headline_members",
    "toolkit_estimator",
    "ensemble_pipeline",
]


def offset_shifts_db(n_sd: int = 1) -> tuple[float, ...]:
    """Candidate per-query offsets of :class:`ilocalg.wifi.OffsetFingerprint`: +-``n_sd`` sd of the measured
    per-phone offset (``n_sd * device_offset_sd_db``, rounded to 2 dB) in 2 dB steps."""
    from ilocalg.sim.measured import param

    half = 2 * int(round(n_sd * param("device_offset_sd_db") / 2))
    return tuple(float(v) for v in range(-half, half + 1, 2))


def offset_grid(fast: bool = False) -> dict:
    """Candidates of the offset-search row, chosen by GroupKFold(PHONEID) CV on training: with and without
    the offset search, powed or exponential representation (Torres-Sospedra et al. 2015), K."""
    shifts = [(0.0,), offset_shifts_db()]
    if fast:
        return {"representation": ["powed"], "shifts_db": shifts, "n_neighbors": [5]}
    return {"representation": ["powed", "exponential"], "shifts_db": shifts, "n_neighbors": [5, 8]}


def ensemble_members(shifts_db=None, three: bool = True) -> list:
    """Members of the toolkit ensemble (:class:`ilocalg.wifi.FingerprintEnsemble`): the offset search on powed
    data (Tsui et al. 2009), the cascade on powed data (Torres-Sospedra et al. 2015's best pair, powed and
    Sorensen) and, with ``three``, the offset search on exponential data, each with the Sorensen distance."""
    from ilocalg.wifi.cascade import CascadeFingerprint
    from ilocalg.wifi.offset import OffsetFingerprint

    sh = offset_shifts_db() if shifts_db is None else tuple(shifts_db)
    members = [("offset_powed", OffsetFingerprint(shifts_db=sh, representation="powed", metric="sorensen")),
               ("cascade_powed", CascadeFingerprint(representation="powed", metric="sorensen"))]
    if three:
        members.append(("offset_exponential", OffsetFingerprint(shifts_db=sh, representation="exponential",
                                                                metric="sorensen")))
    return members


def ensemble_grid(fast: bool = False) -> dict:
    """Candidates of the ensemble row (Pipeline step names ``aps``, ``est``), chosen by GroupKFold(PHONEID) CV
    on training: two or three members (:func:`ensemble_members`). ``K`` is the offset-search CV's choice."""
    if fast:
        return {"est__estimators": [ensemble_members(three=False)]}
    return {"est__estimators": [ensemble_members(three=False), ensemble_members(three=True)]}


def offset_range_grid(fast: bool = False) -> dict:
    """Candidates of the offset-range row (``{"est__estimators": [members, ...]}``), chosen by GroupKFold(PHONEID)
    CV on training: the offset search over +-1 sd or +-2 sd of the measured per-phone offset
    (:func:`offset_shifts_db`; 2 sd holds about 95 % of a normal spread of phones, 1 sd about 68 %), crossed with
    the member sets offset_powed + cascade_powed, offset_powed + offset_exponential and all three
    (:func:`ensemble_members`; members searching +-2 sd are named ``..._2sd``). Fast mode: the powed +
    exponential pair at 1 and 2 sd."""
    cands = []
    for n_sd in (1, 2):
        three = ensemble_members(offset_shifts_db(n_sd), three=True)
        if n_sd == 2:
            three = [(n if n.startswith("cascade") else f"{n}_2sd", e) for n, e in three]
        sets = [[three[0], three[2]]] if fast else [three[:2], [three[0], three[2]], three]
        cands += sets
    return {"est__estimators": cands}


#: Exponents ``a`` of the neighbour weights 1/d**a the spot row's CV chooses among: 1 (scikit-learn's "distance"
#: weights, every earlier offset row), 2 (the i-Loc thesis eq. (2)) and 4 (a steeper weighting towards the nearest
#: reference). Fixed before any validation score of the row was seen.
SPOT_WEIGHT_POWERS = (1.0, 2.0, 4.0)
#: K of the spot-averaged members (a spot stands for about 20 scans of the training set, so K = 1-3 spots).
SPOT_NEIGHBORS = (1, 2, 3)


def spot_grid(base: list, fast: bool = False) -> dict:
    """Candidates of the spot row (``{"est__estimators": [members, ...]}``), chosen by GroupKFold(PHONEID) CV on
    training: for each weight exponent of :data:`SPOT_WEIGHT_POWERS`, the members ``base`` (the offset-range row's
    choice) alone, and ``base`` plus, for each :class:`ilocalg.wifi.OffsetFingerprint` member, the same search
    fitted on the spot-averaged fingerprints (:class:`ilocalg.wifi.SpotAveragedFingerprint`) at each K of
    :data:`SPOT_NEIGHBORS` ("raw + averaged"). The exponent is set on every member that has ``weight_power``;
    member names carry it (``_w2``) where it is not 1, so a member's name stands for one configuration (the
    :func:`ilocalg.wifi.model_selection.ensemble_cv` cache). Fast mode: exponent 1, spot K = 1 or 2.
    """
    from sklearn.base import clone

    from ilocalg.wifi.spots import SpotAveragedFingerprint

    cands = []
    for a in ((1.0,) if fast else SPOT_WEIGHT_POWERS):
        raw = [(n if a == 1 or "weight_power" not in e.get_params() else f"{n}_w{a:g}",
                clone(e).set_params(weight_power=a) if "weight_power" in e.get_params() else e) for n, e in base]
        cands.append(raw)
        for k in ((1, 2) if fast else SPOT_NEIGHBORS):
            cands.append(raw + [(f"spots_{n}_k{k}" + ("" if a == 1 else f"_w{a:g}"),
                                 SpotAveragedFingerprint(clone(e).set_params(n_neighbors=k, weight_power=a)))
                                for n, e in base if "weight_power" in e.get_params()])
    return {"est__estimators": cands}


#: K of every member of the headline row's candidates (:func:`headline_grid`): :func:`offset_grid`'s K values.
HEADLINE_NEIGHBORS = (5, 8)


def rank_member(weight_power: float = 1.0) -> tuple:
    """``(name, estimator)`` of the rank member: WKNN on the ``"rank"`` representation (each heard AP's rank in its
    scan over the number heard; :mod:`ilocalg.wifi.preprocessing`, after Machaj et al. 2011) with the Sorensen
    distance, neighbour weights 1/d**``weight_power``. No offset search: ranks are the same for any increasing map
    of a phone's readings. Named ``rank_sorensen`` (``_w<a>`` where the exponent is not 1)."""
    from ilocalg.wifi.offset import OffsetFingerprint

    name = "rank_sorensen" + ("" if weight_power == 1 else f"_w{weight_power:g}")
    return name, OffsetFingerprint(shifts_db=(0.0,), representation="rank", metric="sorensen",
                                   weight_power=float(weight_power))


def headline_grid(fast: bool = False) -> dict:
    """Candidates of the headline row (``{"est__estimators": [members, ...]}``), chosen by the spot x PHONEID CV
    (:class:`~ilocalg.wifi.model_selection.SpotPhoneKFold`) on training, at each K of :data:`HEADLINE_NEIGHBORS`:
    every member set of :func:`offset_range_grid` (search range +-1 or +-2 sd, three member sets), each crossed with
    :func:`spot_grid` (the weight exponent; raw members alone or raw + spot-averaged at each spot K). The union of
    the candidates the GroupKFold(PHONEID) CVs of the ensemble, offset-range and spot rows chose among, whatever those
    CVs chose, fixed before any score of this CV was seen; and each of those with the rank member
    (:func:`rank_member`, at the candidate's weight exponent) added: a member that no phone's offset or gain moves,
    for the phones the survey never used. Member names stand for one configuration. Fast mode: the fast grids.
    """
    cands, seen = [], set()
    for base in offset_range_grid(fast)["est__estimators"]:
        for members in spot_grid(base, fast)["est__estimators"]:
            key = tuple(n for n, _ in members)
            if key not in seen:
                seen.add(key)
                cands.append(members)
    ranked = []
    for members in cands:
        power = next(e.get_params()["weight_power"] for _, e in members if "weight_power" in e.get_params())
        ranked.append(members + [rank_member(power)])
    return {"est__estimators": cands + ranked}


#: The headline row of notebook 02 as the spot x PHONEID CV chose it on UJIIndoorLoc's training set
#: (:func:`~ilocalg.wifi.model_selection.headline_cv`, then :func:`~ilocalg.wifi.model_selection.device_calibration_cv`:
#: off): K and the member names of :func:`headline_grid`.
#: What ``python -m ilocalg evaluate wifi --method toolkit`` runs (:func:`toolkit_estimator`);
#: :mod:`ilocalg.experiments.wifi_ujiindoorloc` reports whether the ladder's choice still equals it.
TOOLKIT_HEADLINE = {"n_neighbors": 8, "members": ("offset_powed_2sd_w4", "cascade_powed", "offset_exponential_2sd_w4",
                                                  "spots_offset_powed_2sd_k1_w4", "spots_offset_exponential_2sd_k1_w4",
                                                  "rank_sorensen_w4")}


def headline_members(names=TOOLKIT_HEADLINE["members"]) -> list:
    """``[(name, unfitted estimator), ...]`` of the :func:`headline_grid` members called ``names`` (in that order)."""
    by_name = {n: e for members in headline_grid()["est__estimators"] for n, e in members}
    unknown = [n for n in names if n not in by_name]
    if unknown:
        raise ValueError(f"not a member of headline_grid(): {unknown}; known: {sorted(by_name)}")
    return [(n, by_name[n]) for n in names]


def toolkit_estimator(n_neighbors: int | None = None, not_heard_dbm: float | None = None):
    """The toolkit's UJIIndoorLoc headline as one unfitted estimator: :func:`ensemble_pipeline` of
    :data:`TOOLKIT_HEADLINE`'s members at its K (``n_neighbors`` overrides it; the spot-averaged members keep their
    own K), fitted on ``[x_m, y_m, floor, building]`` and predicting that layout. ``not_heard_dbm`` (None: the
    members' -104 dBm) is set on every member. Its settings were chosen on UJIIndoorLoc (the offset-search range
    from that set's measured per-phone offset sd); on another site they are a starting point, not a choice."""
    members = headline_members()
    if not_heard_dbm is not None:
        members = [(n, e.set_params(**{k: float(not_heard_dbm) for k in e.get_params(deep=True)
                                       if k.split("__")[-1] == "not_heard_dbm"})) for n, e in members]
    return ensemble_pipeline(TOOLKIT_HEADLINE["n_neighbors"] if n_neighbors is None else int(n_neighbors), members)


def ensemble_pipeline(n_neighbors: int = 5, estimators=None, min_count: int = 1):
    """``Pipeline([("aps", ApSelector(min_count)), ("est", FingerprintEnsemble(estimators, n_neighbors))])``."""
    from sklearn.pipeline import Pipeline

    from ilocalg.wifi.ensemble import ApSelector, FingerprintEnsemble

    members = ensemble_members() if estimators is None else estimators
    return Pipeline([("aps", ApSelector(min_count)), ("est", FingerprintEnsemble(members, n_neighbors))])
