"""Drop-in replacement for the reference package's ``AcTag`` class.

Users of the reference implementation (``pip install actag``, version 1.0.1)
switch with one line::

    from actag import AcTag        # before
    from pyactag import AcTag      # after

Both packages import side by side (the reference is ``actag``, this one
``pyactag``). The constructor takes the reference's argument names in the
reference's order and ``run_detection(img)`` returns the reference's layout:
a list of ``[tag_id, corner_indices, range_and_azimuth_values]`` with
``corner_indices`` a (4, 2) integer numpy array of [row, column] pairs
(rounded from libactag's sub-pixel corners) and ``range_and_azimuth_values``
a (4, 2) float array of [range m, azimuth rad] pairs (from the sub-pixel
corners), corners in tag order: top-left, top-right, bottom-right,
bottom-left as printed.

Arguments left out (None) take libactag's defaults, which were tuned on
sonar data and differ from the reference's in three places: RANSAC early
exit 0.8 (reference 0.85), required inlier ratio 0.6 (0.8) and bit
corrections min(3, family maximum) (4). Arguments given are mapped onto
libactag's parameters; the few that have no equivalent raise ValueError
when set to something other than the reference's default (see
``_map_arguments``), and the two that only steer the reference's random
draws (``quads_use_same_random_vals``, ``quads_starting_roll_val``) warn
that they have no effect. Values are checked, not converted: a radius of
2.7 or "3" is a TypeError, as elsewhere in pyactag. ``quads_random_seed=None`` gives libactag's fixed seed
1 (libactag is deterministic), not a random seed.
"""

import os
import warnings

from ._args import as_bool, as_int, as_real
from .detection import Detector
from .families import Family, family_names

try:
    import numpy as _np
except ImportError:  # pragma: no cover
    _np = None


def _family_from_argument(tag_family):
    """A built-in family by name, or a family file (.java from the reference
    package, .txt from actag-familygen; a str or os.PathLike path)."""
    if isinstance(tag_family, os.PathLike):
        tag_family = os.fsdecode(tag_family)
    if not isinstance(tag_family, str):
        raise TypeError("tag_family must be a family name or a file path, got {!r}".format(
            tag_family))
    if tag_family.endswith(".java") or tag_family.endswith(".txt"):
        return Family.from_file(tag_family)
    if tag_family in family_names():
        return Family(tag_family)
    raise ValueError("AcTag family '{}' is neither built in ({}) nor a .java/.txt family file"
                     .format(tag_family, ", ".join(family_names())))


def _map_arguments(a, family):
    """Reference arguments (dict, None = not given) -> libactag parameters."""
    p = {}
    if a["median_filter_kernel_radius"] is not None:
        p["median_radius"] = as_int("median_filter_kernel_radius",
                                    a["median_filter_kernel_radius"], 0, 1 << 30)
    if a["adaptive_threshold_kernel_radius"] is not None:
        p["threshold_radius"] = as_int("adaptive_threshold_kernel_radius",
                                       a["adaptive_threshold_kernel_radius"], 0, 1 << 30)
    if a["adaptive_threshold_offset"] is not None:
        off = as_real("adaptive_threshold_offset", a["adaptive_threshold_offset"])
        if off != int(off):
            raise ValueError("adaptive_threshold_offset must be a whole number of grey levels "
                             "in libactag (got {})".format(off))
        p["threshold_offset"] = int(off)
    # Contour size filter. Reference: extents <= diag * (1 + size_tol) and
    # ratio * (1 - area_tol) <= area / diag_area <= 1 + area_tol. libactag uses
    # one tolerance t and the fractions [lo, hi]: lo * (1 - t) <= ... <= hi * (1 + t),
    # so lo = ratio * (1 - area_tol) / (1 - t), hi = (1 + area_tol) / (1 + t). The
    # reference's defaults (0.2, 0.2, 0.1) map to libactag's (0.2, lo 0.1, hi 1.0);
    # with none of them given, libactag's own defaults apply (lo 0.175, actag.h).
    st = 0.2 if a["contours_tag_size_tolerance"] is None else as_real(
        "contours_tag_size_tolerance", a["contours_tag_size_tolerance"])
    at = 0.2 if a["contours_tag_area_tolerance"] is None else as_real(
        "contours_tag_area_tolerance", a["contours_tag_area_tolerance"])
    ratio = 0.1 if a["contours_min_tag_area_ratio"] is None else as_real(
        "contours_min_tag_area_ratio", a["contours_min_tag_area_ratio"])
    for k in ("contours_reject_by_tag_size", "contours_reject_black_shapes",
              "contours_reject_white_shapes", "contours_reject_by_area",
              "quads_use_same_random_vals", "use_optimized_rust_code"):
        if a[k] is not None:
            a[k] = as_bool(k, a[k])  # a bool or numpy bool, no other truthy value
    if a["contours_reject_by_tag_size"] is False:
        raise ValueError("contours_reject_by_tag_size=False: libactag always applies the size "
                         "filter; raise contours_tag_size_tolerance instead")
    if a["contours_reject_black_shapes"] is False or a["contours_reject_white_shapes"] is True:
        raise ValueError("libactag traces white shapes only (contours_reject_black_shapes=True, "
                         "contours_reject_white_shapes=False)")
    if not 0.0 <= st < 1.0:
        raise ValueError("contours_tag_size_tolerance must be in [0, 1) with libactag")
    if a["contours_reject_by_area"] is False:
        p["size_tolerance"] = st
        p["min_area_fraction"] = 0.0
        p["max_area_fraction"] = 1.0e5
    elif any(a[k] is not None for k in ("contours_tag_size_tolerance",
                                         "contours_tag_area_tolerance",
                                         "contours_min_tag_area_ratio")):
        p["size_tolerance"] = st
        p["min_area_fraction"] = max(0.0, ratio * (1.0 - at) / (1.0 - st))
        p["max_area_fraction"] = (1.0 + at) / (1.0 + st)
    if a["quads_random_seed"] is not None:
        seed = as_int("quads_random_seed", a["quads_random_seed"], -(1 << 62), 1 << 62)
        if not 0 <= seed <= 0xFFFFFFFF:
            raise ValueError("quads_random_seed must be 0 .. 2**32-1 in libactag")
        p["seed"] = seed
    for ref, ours in (("quads_points_per_line_ratio", "quad_sample_fraction"),
                      ("quads_dist_for_inlier", "quad_inlier_distance"),
                      ("quads_desired_inlier_ratio", "quad_inlier_ratio"),
                      ("quads_required_inlier_ratio", "quad_min_inlier_ratio"),
                      ("quads_parallel_threshold", "quad_min_parallel_cos")):
        if a[ref] is not None:
            p[ours] = as_real(ref, a[ref])
    if a["quads_use_same_random_vals"]:
        warnings.warn("quads_use_same_random_vals has no effect: libactag's RANSAC is always "
                      "seeded (quads_random_seed)", stacklevel=3)
    if a["quads_starting_roll_val"] is not None:
        warnings.warn("quads_starting_roll_val has no effect: libactag's RANSAC draws come "
                      "from quads_random_seed alone", stacklevel=3)
    n = a["decoding_num_bit_corrections"]
    if n is not None:
        n = as_int("decoding_num_bit_corrections", n, -(1 << 30), 1 << 30)
        # The reference's check: 0 <= n < hamming / 2.
        if n < 0:
            raise ValueError("decoding_num_bit_corrections must be >= 0")
        if n >= family.hamming / 2:
            raise ValueError("decoding_num_bit_corrections must be between 0 and {} with tag "
                             "family {}".format(family.max_corrections, family.name))
        p["max_bit_corrections"] = n
    return p


class AcTag:
    """The reference package's detector class, run by libactag.

    :param min_range: minimum range of the sonar (m), i.e. of the last row.
    :param max_range: maximum range (m), i.e. of the first row.
    :param horizontal_aperture: horizontal aperture (rad); column 0 is +aperture/2.
    :param tag_family: a built-in family name ("AcTag24h10", see
        ``pyactag.family_names()``) or a .java (reference) / .txt
        (actag-familygen) family file (str or ``os.PathLike``).
    :param tag_size: side of the inner white square (m).
    The other parameters: see the module documentation.
    ``libactag_params`` (keyword only, not in the reference) is a dict of
    libactag parameters by their own names (``pyactag.default_params()``).
    """

    def __init__(self,
                 min_range,
                 max_range,
                 horizontal_aperture,
                 tag_family,
                 tag_size,
                 median_filter_kernel_radius=None,
                 adaptive_threshold_kernel_radius=None,
                 adaptive_threshold_offset=None,
                 contours_tag_size_tolerance=None,
                 contours_tag_area_tolerance=None,
                 contours_min_tag_area_ratio=None,
                 contours_reject_black_shapes=None,
                 contours_reject_white_shapes=None,
                 contours_reject_by_tag_size=None,
                 contours_reject_by_area=None,
                 quads_random_seed=None,
                 quads_points_per_line_ratio=None,
                 quads_dist_for_inlier=None,
                 quads_desired_inlier_ratio=None,
                 quads_required_inlier_ratio=None,
                 quads_parallel_threshold=None,
                 quads_use_same_random_vals=False,
                 quads_starting_roll_val=None,
                 decoding_num_bit_corrections=None,
                 use_optimized_rust_code=True,
                 *,
                 libactag_params=None):
        args = dict(locals())
        del args["self"]
        self.min_range = as_real("min_range", min_range)
        self.max_range = as_real("max_range", max_range)
        self.horizontal_aperture = as_real("horizontal_aperture", horizontal_aperture)
        self.tag_size = as_real("tag_size", tag_size)
        self.family = _family_from_argument(tag_family)
        params = _map_arguments(args, self.family)
        extra = dict(libactag_params or {})
        for k in extra:
            if k in params:
                raise TypeError("'{}' set both by a reference argument and by "
                                "libactag_params".format(k))
        params.update(extra)
        params["tag_size"] = self.tag_size
        self.detector = Detector(self.family, min_range=self.min_range,
                                 max_range=self.max_range, aperture=self.horizontal_aperture,
                                 **params)

    @staticmethod
    def _as_frame(sonar_img):
        """The reference accepts any numpy image; libactag reads uint8/uint16."""
        if _np is None or not isinstance(sonar_img, _np.ndarray):
            return sonar_img
        if sonar_img.ndim != 2:
            raise ValueError("sonar_img must be a 2-D greyscale image (rows = ranges, columns = "
                             "beams), not shape {}".format(sonar_img.shape))
        if sonar_img.dtype in (_np.uint8, _np.uint16):
            return sonar_img
        if sonar_img.dtype.kind in "iub":
            lo, hi = (int(sonar_img.min()), int(sonar_img.max())) if sonar_img.size else (0, 0)
            if lo >= 0 and hi <= 255:
                return sonar_img.astype(_np.uint8)
            if lo >= 0 and hi <= 65535:
                return sonar_img.astype(_np.uint16)
        raise TypeError("sonar_img must hold integer grey levels 0..65535 (uint8 or uint16), "
                        "not {}".format(sonar_img.dtype))

    def _format(self, dets):
        out = []
        for d in dets:
            rc = [[int(round(y)), int(round(x))] for x, y in d.corners_xy]
            ra = [[r, a] for r, a in d.corners_polar]
            if _np is not None:
                out.append([int(d.id), _np.array(rc, dtype=int), _np.array(ra, dtype=float)])
            else:  # pragma: no cover
                out.append([int(d.id), rc, ra])
        return out

    def run_detection(self, sonar_img):
        """Detect tags: a list of ``[tag_id, corner_indices, range_and_azimuth_values]``.

        ``sonar_img``: 2-D image; first row = max range, last row = min
        range, first column = max azimuth, last column = min azimuth.
        """
        return self._format(self.detector.detect(self._as_frame(sonar_img)))

    # The reference's two implementations; both are libactag here.
    run_detection_rust = run_detection
    run_detection_python = run_detection

    def visualize_detection(self, sonar_img):
        """``run_detection`` plus a matplotlib figure of the input, the
        median-filtered and binary stages and the detections."""
        import matplotlib.pyplot as plt
        frame = self._as_frame(sonar_img)
        res = self.detector.run(frame, stages=True)
        fig, axes = plt.subplots(1, 4, figsize=(16, 4))
        for ax, img, title in ((axes[0], frame, "Input Image"),
                               (axes[1], res.stages["filtered"], "Filtered Image"),
                               (axes[2], res.stages["binary"], "Binarized Image"),
                               (axes[3], frame, "Tag Detections")):
            ax.imshow(img, cmap="gray")
            ax.set_title(title)
        for d in res.detections:
            xs = [p[0] for p in d.corners_xy] + [d.corners_xy[0][0]]
            ys = [p[1] for p in d.corners_xy] + [d.corners_xy[0][1]]
            axes[3].plot(xs, ys, "g-")
            axes[3].plot(d.corners_xy[0][0], d.corners_xy[0][1], "ro")
            cx, cy = d.center_xy
            axes[3].text(cx, cy, str(d.id), color="cyan")
        plt.show()
        return self._format(res.detections)
