"""UMBmark: unequal wheel diameters and the wheel base from two square tests.

Borenstein and Feng's University of Michigan Benchmark (IEEE T-RA 1996): the
robot drives a square of side L, on odometry, clockwise n times and
counter-clockwise n times; after each run the return error

    epsilon = true return position - odometry's return position

is taken in the frame of the run's start (x forward, y left). Two systematic
errors explain the two clusters of errors:

* the wheel base is ``Eb`` times what odometry assumes, so every turn that
  odometry calls 90 degrees is really 90 / Eb = 90 - alpha;
* the right wheel's diameter is ``Ed`` times the left one's, so every leg
  that odometry calls straight really curves left by beta.

To first order (the paper's section 5) the centres of gravity of the
clusters are

    x_cw  = -2 L (beta + alpha)     y_cw  = -2 L (beta + alpha)
    x_ccw =  2 L (beta - alpha)     y_ccw = -2 L (beta - alpha)

so alpha = (x_cw + x_ccw) / (-4 L) and beta = (x_cw - x_ccw) / (-4 L), or
from y, alpha = (y_cw - y_ccw) / (-4 L) and beta = (y_cw + y_ccw) / (-4 L)
(the mean of the two is taken), and then

    R  = (L / 2) / sin(beta / 2)          the radius of the curved legs
    Ed = (R + b / 2) / (R - b / 2)        b: the wheel base
    Eb = (pi / 2) / (pi / 2 - alpha)

That is only the first step here. The terms the paper drops grow with the
square of the curve: wheels 2 % apart curve a 1 m side by 4 to 5 degrees
(a 26 to 23 cm base), and on a 23 cm base the first-order Eb is then 0.2 %
too large (0.4 % with wheels 2.7 % apart, 0.6 % with the base 1.5 % short
as well), so a corrected robot turns 0.7 to 2 degrees wrong per full
turn. So :func:`analyse` takes the
first-order Ed and Eb as the start of a least-squares fit of the model the
formulas approximate, computed exactly (:func:`square_return`: each side
an arc, each turn in place about a point off the axle's centre when the
wheels differ), to the two centres of gravity.

The measure of the result is E_max,syst, the larger distance of the two
centres of gravity from the origin. The corrections follow
diff_drive_controller's names: each wheel radius multiplied by 2 / (Ed + 1)
(left) and 2 / (1 / Ed + 1) (right), which keeps their mean, and the wheel
separation by Eb.

Random errors scatter the return positions too, and with few runs or a
noisy robot the centres of gravity may lie as far from zero as the scatter
puts them by chance: then the "correction" is noise, and setting it makes
the robot worse. So each cluster's scatter is reported,

    s  = sqrt(sum |e_i - cg|^2 / (n - 1))   standard deviation of the n
                                            return positions about their
                                            centre of gravity (x and y
                                            together)
    se = s / sqrt(n)                        standard error of the centre
                                            of gravity

and the correction is *supported* when at least one centre of gravity lies
farther from zero than chance puts it in ``FALSE_ALARM`` (5 %) of
benchmarks of a robot without systematic errors: for each cluster,

    |cg| / se > k(n),  k(n)^2 = (d / 2) ((FALSE_ALARM / 2)^(-2 / d) - 1),
    d = 2 (n - 1)

the exact test for the mean of n points with the same Gaussian scatter in
x and y (|cg|^2 / se^2 follows the F distribution with 2 and d degrees of
freedom), at FALSE_ALARM / 2 per cluster. k is about 2 standard errors:
2.5 for 5 runs, 2.0 for 20, 1.9 for very many; 6.2 for 2 runs, whose
scatter is itself a rough guess. One run each way shows no scatter and
supports nothing. Nor does a centre of gravity within ``RESOLUTION`` (2 mm)
of zero, whatever the scatter: a return position is read off a tape to
about a millimetre in x and in y, at the start mark and again where the
robot stopped, so a return closer than that is a perfect one as far as
the tape tells. Runs that scatter by nothing (a simulator without noise)
need that floor most: any residual would be "beyond the noise", and a
correction that worked would be followed by one of x1.00006.
When a correction is not supported by runs that show
their scatter, the robot is calibrated as far as they can tell: there is
no correction to apply (:func:`calibrated`), and the runs each way that
would make a systematic error of the size measured stand out are the
smallest n with |cg| sqrt(n) / s > k(n).

The node's plain parts are here too (its ROS side is umbmark_ros): the run
labels, reading a position typed at the terminal, the results file (YAML)
and the texts it logs. No rospy here.
"""
import math
from collections import namedtuple

import numpy as np
import yaml

from rbx1_nav.motion.course.course import Course
from rbx1_nav.motion.course.steps import Drive, Pause, Turn

__all__ = ['relative', 'square_course', 'check_errors', 'analyse',
           'analyse_runs', 'Result', 'Scatter', 'FALSE_ALARM', 'RESOLUTION', 'critical',
           'calibrated',
           'runs_needed', 'square_return', 'first_order',
           'corrections', 'report', 'plot', 'run_label', 'parse_position',
           'evaluate', 'results_record', 'save', 'load', 'compare_text',
           'rerun_text']

CW, CCW = 'cw', 'ccw'
FALSE_ALARM = 0.05  # chance of a correction "supported" by noise alone
#: A centre of gravity this close to zero (m) is a perfect return as far as
#: a tape measure tells (the module's docstring): it supports no correction.
RESOLUTION = 0.002
#: Return positions scattered by less than this (m) are the same run
#: repeated: a simulator without noise, rounding apart.
IDENTICAL = 1e-6


def relative(start, end):
    """(x, y) of ``end`` in the frame of ``start`` (x forward, y left)."""
    dx, dy = end.x - start.x, end.y - start.y
    c, s = math.cos(start.yaw), math.sin(start.yaw)
    return (c * dx + s * dy, -s * dx + c * dy)


def square_course(side, clockwise, linear_speed, angular_speed, approach,
                  pause=1.0, label='', breakaway=None):
    """One UMBmark run: [drive ``side``, turn 90 degrees] x 4, closed loop;
    ``breakaway``: the creep speeds every run shares (course.Course)."""
    angle = -math.pi / 2 if clockwise else math.pi / 2
    steps = []
    for k in range(1, 5):
        name = '%s side %d/4' % (label, k)
        steps += [Drive(side, linear_speed, approach=approach,
                        heading_rate=angular_speed, label=name),
                  Pause(pause),
                  Turn(angle, angular_speed, approach=approach, label=name),
                  Pause(pause)]
    return Course(steps, breakaway)


def check_errors(errors, runs, side, name='errors'):
    """``errors`` as an (runs, 2) array, or ValueError saying what is wrong.

    A return error must be finite and smaller than the square's side: a
    larger one is a measurement in the wrong unit or the wrong run.
    """
    try:
        array = np.array(errors, dtype=float)
    except (TypeError, ValueError):
        raise ValueError('%s must be a list of %d [x, y] pairs (metres), got %.200r'
                         % (name, runs, errors))
    if array.shape != (runs, 2):
        raise ValueError('%s must be a list of %d [x, y] pairs (metres), got %.200r'
                         % (name, runs, errors))
    for k, (x, y) in enumerate(array):
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ValueError('%s[%d] = [%r, %r] is not a finite position'
                             % (name, k, x, y))
        if math.hypot(x, y) >= side:
            raise ValueError(
                '%s[%d] = [%g, %g] is %.3f m from the start, more than the '
                'square\'s side (%g m): a wrong unit (metres) or another run?'
                % (name, k, x, y, math.hypot(x, y), side))
    return array


Result = namedtuple('Result', 'side wheel_separation cw ccw cg_cw cg_ccw '
                              'e_max alpha beta ed eb scatter_cw scatter_ccw '
                              'supported')
Result.__doc__ = """What UMBmark found: the return errors of each direction
(arrays of [x, y]), their centres of gravity, E_max,syst (m), alpha and beta
(rad), Ed and Eb, each cluster's :class:`Scatter`, and whether the data
support a correction (see the module's docstring)."""

Scatter = namedtuple('Scatter', 'runs sd se distance offset')
Scatter.__doc__ = """A cluster's scatter: its number of runs, the standard
deviation of its return positions about their centre of gravity and the
standard error of that centre (m; NaN for one run), the centre's
distance from zero in standard errors (NaN for one run), and in metres."""


def critical(runs):
    """k(runs): the standard errors from zero beyond which a centre of
    gravity of ``runs`` return positions is not chance (module docstring)."""
    d = 2.0 * (runs - 1)
    return math.sqrt(d / 2.0 * ((FALSE_ALARM / 2.0) ** (-2.0 / d) - 1.0))


def scatter(errors, cg):
    """The :class:`Scatter` of the return ``errors`` about ``cg``."""
    n = len(errors)
    distance = float(math.hypot(*cg))
    if n < 2:
        return Scatter(n, math.nan, math.nan, math.nan, distance)
    sd = math.sqrt(float(np.sum((errors - cg) ** 2)) / (n - 1))
    if sd < IDENTICAL:  # identical runs (a simulator without noise)
        return Scatter(n, 0.0, 0.0, math.inf if distance > 0.0 else 0.0, distance)
    se = sd / math.sqrt(n)
    return Scatter(n, sd, se, distance / se, distance)


def supports(scatters):
    """Whether clusters of these :class:`Scatter` support a correction: a
    centre of gravity of more than one run farther from zero than
    :func:`critical` standard errors, and than RESOLUTION, in either
    direction."""
    return any(spread.runs > 1 and spread.distance > critical(spread.runs)
               and spread.offset > RESOLUTION for spread in scatters)


def calibrated(result):
    """True when runs that show their scatter (two or more each way)
    support no correction: the robot is calibrated as far as they tell.
    One run each way shows no scatter, and tells neither."""
    return (not result.supported
            and min(result.scatter_cw.runs, result.scatter_ccw.runs) > 1)


def runs_needed(result, most=1000):
    """About how many runs each way would make a systematic error of the
    size measured stand out from the scatter measured: the fewer of the two
    clusters'; None when there is no scatter to go by (one run), inf past
    ``most``."""
    needed = []
    for cg, spread in ((result.cg_cw, result.scatter_cw),
                       (result.cg_ccw, result.scatter_ccw)):
        if math.isnan(spread.sd):
            continue
        ratio = math.hypot(*cg) / spread.sd if spread.sd > 0 else math.inf
        needed.append(next((n for n in range(2, most + 1)
                            if ratio * math.sqrt(n) > critical(n)), math.inf))
    return min(needed) if needed else None


def square_return(ed, eb, side, wheel_separation, clockwise):
    """(x, y) where a run ends, in its start's frame, when its odometry
    (wheels of equal size, the base ``wheel_separation``) says it drove a
    perfect square back to the start, on wheels whose diameters are ``ed``
    to one (right to left, their mean right) and a base ``eb`` times the
    assumed one: the paper's model without its approximations."""
    left, right = 2.0 / (ed + 1.0), 2.0 * ed / (ed + 1.0)  # true / assumed size
    base = eb * wheel_separation
    turn = (-1.0 if clockwise else 1.0) * math.pi / 4.0 * wheel_separation
    x = y = heading = 0.0
    for _ in range(4):
        # A side (odometry: both wheels roll ``side``), then a turn in
        # place (odometry: the wheels roll -turn and +turn).
        for wheel_left, wheel_right in ((side * left, side * right),
                                        (-turn * left, turn * right)):
            travel = 0.5 * (wheel_left + wheel_right)
            change = (wheel_right - wheel_left) / base
            chord = travel if change == 0.0 else 2.0 * travel / change * math.sin(change / 2.0)
            x += chord * math.cos(heading + change / 2.0)
            y += chord * math.sin(heading + change / 2.0)
            heading += change
    return x, y


def _fit(ed, eb, cg_cw, cg_ccw, side, wheel_separation, steps=20):
    """Ed and Eb of the exact model (:func:`square_return`) nearest, in
    least squares, to the two centres of gravity, from (``ed``, ``eb``)
    on by Gauss-Newton steps."""
    measured = np.concatenate([cg_cw, cg_ccw])

    def model(p):
        return np.concatenate([square_return(p[0], p[1], side, wheel_separation, clockwise)
                               for clockwise in (True, False)])

    p = np.array([ed, eb])
    for _ in range(steps):
        now = model(p)
        jacobian = np.column_stack([(model(p + d) - now) / 1e-7
                                    for d in np.eye(2) * 1e-7])
        step = np.linalg.lstsq(jacobian, measured - now, rcond=None)[0]
        p = p + step
        if not np.all(np.isfinite(p)):  # no fit: the first-order figures
            return ed, eb
        if np.max(np.abs(step)) < 1e-12:
            break
    return float(p[0]), float(p[1])


def first_order(cg_cw, cg_ccw, side, wheel_separation):
    """(Ed, Eb) by the paper's first-order formulas from the two centres of
    gravity, its x and y formulas averaged (the module's docstring)."""
    alpha = ((cg_cw[0] + cg_ccw[0]) + (cg_cw[1] - cg_ccw[1])) / (-8.0 * side)
    beta = ((cg_cw[0] - cg_ccw[0]) + (cg_cw[1] + cg_ccw[1])) / (-8.0 * side)
    if beta == 0.0:
        ed = 1.0
    else:
        radius = (side / 2.0) / math.sin(beta / 2.0)
        half = wheel_separation / 2.0
        ed = (radius + half) / (radius - half)
    return ed, (math.pi / 2.0) / (math.pi / 2.0 - alpha)


def analyse(cw, ccw, side, wheel_separation):
    """Ed and Eb from the return errors of both directions: the paper's
    arithmetic, then the exact model fitted (the module's docstring)."""
    cw, ccw = np.asarray(cw, dtype=float), np.asarray(ccw, dtype=float)
    cg_cw, cg_ccw = cw.mean(axis=0), ccw.mean(axis=0)
    e_max = max(np.hypot(*cg_cw), np.hypot(*cg_ccw))
    ed, eb = first_order(cg_cw, cg_ccw, side, wheel_separation)
    ed, eb = _fit(ed, eb, cg_cw, cg_ccw, side, wheel_separation)
    # The turn error and the curve per side of the fitted robot.
    alpha = math.pi / 2.0 * (1.0 - 1.0 / eb)
    beta = 2.0 * side * (ed - 1.0) / (ed + 1.0) / (eb * wheel_separation)
    scatters = scatter(cw, cg_cw), scatter(ccw, cg_ccw)
    return Result(side, wheel_separation, cw, ccw, cg_cw, cg_ccw, float(e_max),
                  float(alpha), float(beta), float(ed), float(eb), *scatters,
                  supports(scatters))


def analyse_runs(odometry, measured, runs, side, wheel_separation):
    """:func:`analyse` of whole benchmark: odometry's and the true return
    positions of the ``runs`` clockwise runs, then the counter-clockwise."""
    errors = np.asarray(measured, dtype=float) - np.asarray(odometry, dtype=float)
    return analyse(errors[:runs], errors[runs:], side, wheel_separation)


def corrections(result):
    """The factors to multiply the driver's settings by.

    diff_drive_controller's three multipliers, and for a driver with only
    the TurtleBot's two scale corrections, the odom_angular_scale_correction
    that removes Eb (odometry turns Eb times too far).
    """
    ed, eb = result.ed, result.eb
    return {'left_wheel_radius_multiplier': 2.0 / (ed + 1.0),
            'right_wheel_radius_multiplier': 2.0 / (1.0 / ed + 1.0),
            'wheel_separation_multiplier': eb,
            'odom_angular_scale_correction': 1.0 / eb}


def report(result):
    """The lines that tell the user what was measured and, when the data
    support it, what to set; else why not and how many runs would do."""
    lines = []
    for label, errors in ((CW, result.cw), (CCW, result.ccw)):
        lines.append('%s return errors (x, y mm): %s' % (label, ', '.join(
            '(%+.1f, %+.1f)' % (1000 * x, 1000 * y) for x, y in errors)))
    lines.append('scatter: %s' % '; '.join(
        '%s %d run%s, %s' % (label, spread.runs, 's' * (spread.runs > 1),
                             'no scatter measurable' if math.isnan(spread.sd)
                             else 'identical to 0.001 mm (no noise)' if spread.sd == 0.0
                             else 'standard deviation %.1f mm, centre of '
                             'gravity +- %.1f mm (standard error), %.1f '
                             'standard errors from zero' % (
                                 1000 * spread.sd, 1000 * spread.se,
                                 spread.distance))
        for label, spread in ((CW, result.scatter_cw),
                              (CCW, result.scatter_ccw))))
    lines += [
        'centres of gravity: cw (%+.1f, %+.1f) mm, ccw (%+.1f, %+.1f) mm; '
        'E_max,syst %.1f mm' % (1000 * result.cg_cw[0], 1000 * result.cg_cw[1],
                                1000 * result.cg_ccw[0],
                                1000 * result.cg_ccw[1], 1000 * result.e_max),
        'alpha %+.3f deg (turn error), beta %+.3f deg (curve per side)'
        % (math.degrees(result.alpha), math.degrees(result.beta)),
        'Ed (right/left wheel diameter) %.5f, Eb (true/assumed wheel base) %.5f'
        % (result.ed, result.eb),
    ]
    if not result.supported:
        return lines + [calibrated_text(result) if calibrated(result)
                        else unsupported(result)]
    lines.append('E_max,syst is beyond the noise (a centre of gravity '
                 'farther from zero than chance puts it in %g %% of '
                 'benchmarks): the correction is supported'
                 % (100 * FALSE_ALARM))
    factors = corrections(result)
    lines.append(
        'diff_drive_controller: multiply left_wheel_radius_multiplier by '
        '%.5f, right_wheel_radius_multiplier by %.5f, '
        'wheel_separation_multiplier by %.5f' % (
            factors['left_wheel_radius_multiplier'],
            factors['right_wheel_radius_multiplier'],
            factors['wheel_separation_multiplier']))
    lines.append(
        'TurtleBot driver: multiply odom_angular_scale_correction by %.5f '
        '(removes Eb); Ed needs per-wheel radii, which that driver does not '
        'have' % factors['odom_angular_scale_correction'])
    return lines


def calibrated_text(result):
    """The line saying that the robot is calibrated (:func:`calibrated`):
    no correction to apply, and how many runs would show an error of the
    size measured."""
    runs = min(result.scatter_cw.runs, result.scatter_ccw.runs)
    if result.e_max <= RESOLUTION:
        return ('the robot is calibrated: %sE_max,syst %.1f mm is within %g mm '
                'of a perfect return (what a tape measure tells apart), so there '
                'is no correction to apply' % (
                    'its runs are identical (no noise) and '
                    if result.scatter_cw.sd == result.scatter_ccw.sd == 0.0 else '',
                    1000 * result.e_max, 1000 * RESOLUTION))
    needed = runs_needed(result)
    if math.isinf(needed):
        more = ('no systematic error shows against this scatter (over 1000 '
                'runs each way would not tell one of this size)')
    else:
        more = ('a systematic error of this size would take about %d runs '
                'each way (%d more) to tell from the scatter' % (
                    max(needed, runs + 1), max(needed - runs, 1)))
    return ('the robot is calibrated, as far as %d runs each way tell: '
            'E_max,syst %.1f mm is within the noise (neither centre of gravity '
            'lies farther from zero than chance puts it in %g %% of benchmarks, '
            '%.1f standard errors for %d runs), so there is no correction to '
            'apply (one would correct noise); %s' % (
                runs, 1000 * result.e_max, 100 * FALSE_ALARM, critical(runs),
                runs, more))


def unsupported(result):
    """The line for runs that show no scatter (one each way): they tell
    neither a correction nor that the robot is calibrated."""
    return ('with one run each way no scatter can be measured, so E_max,syst '
            '%.1f mm cannot be told from noise: no correction is given, and '
            'the robot is not shown to be calibrated either; run at least 2 '
            'each way (5 or more is better)' % (1000 * result.e_max))


def plot(results, path, labels=None):
    """Draw the return errors, clusters and centres of gravity; save a PNG.

    ``results``: one Result, or several (e.g. before and after correction),
    drawn on the same axes with ``labels``.
    """
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    labels = labels or ['run %d' % (k + 1) for k in range(len(results))]
    fig, ax = plt.subplots(figsize=(7, 7))
    colours = {CW: 'tab:blue', CCW: 'tab:red'}
    for k, (result, label) in enumerate(zip(results, labels)):
        filled = k == len(results) - 1
        for direction, errors, cg in ((CW, result.cw, result.cg_cw),
                                      (CCW, result.ccw, result.cg_ccw)):
            mm = 1000 * np.asarray(errors)
            ax.scatter(mm[:, 0], mm[:, 1], s=30, color=colours[direction],
                       facecolors=colours[direction] if filled else 'none',
                       label='%s %s runs' % (label, direction))
            ax.scatter([1000 * cg[0]], [1000 * cg[1]], s=160,
                       marker='X' if filled else 'P', alpha=1.0 if filled else 0.5,
                       color=colours[direction], edgecolors='black',
                       label='%s %s centre of gravity' % (label, direction))
        ax.add_patch(plt.Circle((0, 0), 1000 * result.e_max, fill=False,
                                linestyle='--' if filled else ':',
                                color='grey'))
    ax.axhline(0, color='lightgrey', zorder=0)
    ax.axvline(0, color='lightgrey', zorder=0)
    ax.set_aspect('equal', adjustable='datalim')
    ax.set_xlabel('x error (mm, forward at the start)')
    ax.set_ylabel('y error (mm, left at the start)')
    ax.set_title('UMBmark, %g m square\n%s' % (results[-1].side, '; '.join(
        '%s E_max,syst %.1f mm' % (label, 1000 * r.e_max)
        for r, label in zip(results, labels))))
    ax.legend(fontsize='small', loc='best')
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def run_label(k, runs, clockwise):
    """'run 3/10 (cw)': run ``k`` (from 0) of ``runs`` in all."""
    return 'run %d/%d (%s)' % (k + 1, runs, CW if clockwise else CCW)


def parse_position(answer, side):
    """The (x, y) typed as ``answer`` ("x y" or "x, y", metres) for a square
    of ``side``; ValueError with the hint to show the user if unusable."""
    try:
        x, y = (float(part) for part in answer.replace(',', ' ').split())
    except ValueError:
        raise ValueError('type two numbers in metres, e.g. "0.012 -0.004"')
    try:
        return tuple(check_errors([[x, y]], 1, side, 'position')[0])
    except ValueError as err:
        raise ValueError('%s; try again' % err)


def evaluate(odometry, measured, runs, side, wheel_separation):
    """Check odometry's and the true return positions (2 x ``runs`` each,
    clockwise runs first) and analyse them: (odometry, measured, Result),
    the positions as arrays. ValueError names the node's parameter
    (~measurements, ~odometry) whose value is unusable."""
    count = 2 * runs
    measured = check_errors(measured, count, side, '~measurements')
    odometry = check_errors(odometry, count, side, '~odometry')
    result = analyse_runs(odometry, measured, runs, side, wheel_separation)
    return odometry, measured, result


def results_record(result, runs, odometry, measured):
    """What the results file holds: the benchmark's settings and positions,
    the figures, each direction's scatter and the corrections (None when
    the data do not support them)."""
    return {
        'side': result.side, 'runs': runs,
        'wheel_separation': result.wheel_separation,
        'odometry': odometry.tolist(), 'measurements': measured.tolist(),
        'e_max_syst': result.e_max, 'ed': result.ed, 'eb': result.eb,
        'scatter': {label: {'sd': spread.sd, 'se': spread.se} for label, spread
                    in ((CW, result.scatter_cw), (CCW, result.scatter_ccw))},
        'supported': result.supported,
        'corrections': corrections(result) if result.supported else None}


def save(path, result, runs, odometry, measured):
    """Write :func:`results_record` to ``path`` (YAML)."""
    with open(path, 'w') as f:
        yaml.safe_dump(results_record(result, runs, odometry, measured), f)


def load(path):
    """The Result of a results file :func:`save` wrote."""
    with open(path) as f:
        saved = yaml.safe_load(f)
    return analyse_runs(saved['odometry'], saved['measurements'],
                        saved['runs'], saved['side'],
                        saved['wheel_separation'])


def compare_text(before, after):
    """E_max,syst of an earlier Result and this one, and their ratio; an
    E_max,syst under 0.001 mm (a simulator without systematic errors) is
    told as such, as :func:`report` tells identical runs, not as a ratio to
    rounding."""
    if after.e_max < IDENTICAL:
        return ('E_max,syst before %.1f mm, after zero to 0.001 mm (no '
                'systematic error left)' % (1000 * before.e_max))
    return 'E_max,syst before %.1f mm, after %.1f mm (%.1fx)' % (
        1000 * before.e_max, 1000 * after.e_max, before.e_max / after.e_max)


def rerun_text(runs, side, odometry):
    """What to measure after runs driven without ground truth or terminal,
    and the command that analyses the measurements with odometry's
    return positions ``odometry``."""
    return ('all runs done. Measure where each run stopped (x forward, y '
            'left of its start, metres; clockwise runs first), then run:\n'
            "  rosrun rbx1_nav umbmark.py _runs:=%d _side:=%g _odometry:='%s' "
            "_measurements:='[[x1, y1], ...]'" % (
                runs, side, [[round(x, 4), round(y, 4)] for x, y in odometry]))
