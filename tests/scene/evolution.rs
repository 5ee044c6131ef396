//! `[evolution]`: load paths. The oracle of every factor is the table written in the test
//! (interpolated by hand), of every generated path the formula of docs/scene-format.md
//! (`start + k (end − start)/N`, the tables' times inserted), and every mistake is an
//! `Error::Scene` at the line of the offending value.

use crate::edit::Edit;
use crate::{line_of, parse, scene_error, two_triangles, BASE};
use signorini::error::Error;
use signorini::scene::{
    BodiesBuilder, EvolutionSpec, FrictionSpec, LoadFunction, ObstacleSpec, SceneBuilder, BUILT_IN_RUST,
};
use std::path::Path;

/// A block pressed on a rigid floor, then pushed sideways back and forth (the example of
/// docs/scene-format.md).
const PRESS_PUSH: &str = r#"title = "press then push"

[mesh]
shape = "rectangle"
size = [1.0, 1.0]
cell_size = 0.25

[material]
young = 1e9
poisson = 0.3

[loads]
body_force = [0.0, -1e4]
name = "weight"

[[traction]]
part = "top"
pressure = 1e6
name = "press"

[[traction]]
part = "right"
traction = [-2e5, 0.0]
name = "shear"

[[traction]]
part = "left"
traction = [1e5, 0.0]

[[dirichlet]]
point = [0.0, 1.0]
ux = 1e-4
name = "press"

[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
friction = "coulomb"
mu = 0.3
motion = [0.01, -0.002]
name = "slide"

[evolution]
steps = 4
monitor = "top"
profiles = [1.0, 2.0]

[evolution.factor]
press = [[0, 0], [1, 1], [4, 1]]
shear = [[0, 0], [1, 0], [2, 1], [3, -1], [4, 1]]
weight = [[0, 1], [4, 1]]
slide = [[0, 0], [2, 0], [4.0, 2.5]]
"#;

#[track_caller]
fn evolution(text: &str) -> EvolutionSpec {
    parse(text).unwrap_or_else(|e| panic!("{e}\n{text}")).evolution.expect("[evolution]")
}

#[track_caller]
fn close(a: f64, b: f64) {
    assert!((a - b).abs() <= 1e-14 * (1.0 + b.abs()), "{a} != {b}");
}

#[test]
fn a_load_path_parses_and_its_factors_interpolate_the_tables() {
    let s = parse(PRESS_PUSH).unwrap();
    let e = s.evolution.clone().unwrap();
    // Names on every kind of load.
    let names: Vec<Option<&str>> = s.tractions.iter().map(|t| t.name.as_deref()).collect();
    assert_eq!(names, [Some("press"), Some("shear"), None]);
    assert_eq!(s.dirichlet[0].name.as_deref(), Some("press"));
    assert_eq!(s.body_force_name.as_deref(), Some("weight"));
    let c = s.contact.as_ref().unwrap();
    assert_eq!((c.motion, c.name.as_deref()), (Some([0.01, -0.002]), Some("slide")));

    // steps = 4 over [0, 4]: 1, 2, 3, 4, the tables' times 1, 2, 3 already there.
    assert_eq!(e.start, 0.0);
    assert_eq!(e.start(), 0.0);
    assert_eq!(e.times, [1.0, 2.0, 3.0, 4.0]);
    assert_eq!((e.end(), e.ramp_end()), (4.0, 4.0));
    assert_eq!(e.monitor.as_deref(), Some("top"));
    assert_eq!(e.monitor_at.as_ref().map(|l| l.line), Some(line_of(PRESS_PUSH, "monitor = ")));
    assert_eq!(e.profiles, [1.0, 2.0]);
    assert_eq!(e.at.line, line_of(PRESS_PUSH, "[evolution]"));
    let order: Vec<&str> = e.factors.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(order, ["press", "shear", "weight", "slide"], "file order");
    assert_eq!(e.factors[1].at.line, line_of(PRESS_PUSH, "shear = [[0"));

    // At the breakpoints: the table's values.
    for (t, press, shear, slide) in
        [(0.0, 0.0, 0.0, 0.0), (1.0, 1.0, 0.0, 0.0), (2.0, 1.0, 1.0, 0.0), (3.0, 1.0, -1.0, 1.25), (4.0, 1.0, 1.0, 2.5)]
    {
        assert_eq!(e.factor(Some("press"), t), press, "press at {t}");
        assert_eq!(e.factor(Some("shear"), t), shear, "shear at {t}");
        assert_eq!(e.factor(Some("slide"), t), slide, "slide at {t}");
        assert_eq!(e.factor(Some("weight"), t), 1.0);
        // unnamed: t / t_end, t_end = 4
        assert_eq!(e.factor(None, t), t / 4.0);
    }
    // Between them: linear (by hand: press 0 → 1 on [0, 1]; shear 1 → −1 on [2, 3]).
    close(e.factor(Some("press"), 0.25), 0.25);
    close(e.factor(Some("shear"), 2.25), 0.5);
    close(e.factor(Some("shear"), 2.75), -0.5);
    close(e.factor(Some("shear"), 3.5), 0.0);
    close(e.factor(Some("slide"), 2.4), 0.5);
    close(e.factor(None, 1.5), 0.375);
    // Outside a table: its end values.
    let f = LoadFunction { name: "x".into(), points: vec![[1.0, 2.0], [3.0, -2.0]], at: e.at.clone() };
    assert_eq!((f.value(0.0), f.value(1.0), f.value(2.0), f.value(3.0), f.value(9.0)), (2.0, 2.0, 0.0, -2.0, -2.0));
    assert_eq!((f.first_time(), f.last_time()), (1.0, 3.0));
    let empty = LoadFunction { points: Vec::new(), ..f.clone() };
    assert!(empty.value(1.0).is_nan() && empty.first_time().is_nan(), "no rows: no value, no panic");

    // The obstacle at a factor: moved by factor · motion.
    assert_eq!(c.obstacle_at(0.0), c.obstacle);
    assert_eq!(c.obstacle_at(2.5), ObstacleSpec::Line { point: [0.025, -0.005], normal: [0.0, 1.0] });
    let circle = ObstacleSpec::Circle { center: [1.0, 2.0], radius: 0.5 };
    assert_eq!(circle.translated([1.0, -1.0]), ObstacleSpec::Circle { center: [2.0, 1.0], radius: 0.5 });
    let polyline = ObstacleSpec::Polyline { points: vec![[0.0, 0.0], [1.0, 0.5]] };
    assert_eq!(polyline.translated([0.5, 0.5]), ObstacleSpec::Polyline { points: vec![[0.5, 0.5], [1.5, 1.0]] });

    // The monitor is checked against the mesh (two_triangles has it).
    s.check_against_mesh(&two_triangles()).unwrap();
    // Written and read back: the same path.
    let again = parse(&s.to_toml()).unwrap().evolution.unwrap();
    assert_eq!(
        (again.start, &again.times, &again.profiles, &again.monitor),
        (e.start, &e.times, &e.profiles, &e.monitor)
    );
    let points = |e: &EvolutionSpec| e.factors.iter().map(|f| (f.name.clone(), f.points.clone())).collect::<Vec<_>>();
    assert_eq!(points(&again), points(&e));
    assert_eq!(s.validated().unwrap().evolution, s.evolution);
}

/// `[evolution] steps = N` without tables: t = k/N, every load proportional.
#[test]
fn steps_without_tables_load_proportionally() {
    let e = evolution(&format!("{BASE}\n[evolution]\nsteps = 4\n"));
    assert_eq!(e.start, 0.0);
    assert_eq!(e.times, [0.25, 0.5, 0.75, 1.0]);
    assert!(e.factors.is_empty());
    assert_eq!((e.end(), e.ramp_end()), (1.0, 1.0));
    for t in [0.0, 0.1, 0.25, 0.6, 1.0] {
        assert_eq!(e.factor(None, t), t);
    }
    assert_eq!(e.profiles, [1.0], "the default: the end of the path");
    assert_eq!(e.monitor, None);
    // Listed times and a start, and no profile.
    let e = evolution(&format!("{BASE}\n[evolution]\nstart = 0.2\ntimes = [0.3, 0.7, 1]\nprofiles = []\n"));
    assert_eq!((e.start, e.times.as_slice(), e.profiles.as_slice()), (0.2, &[0.3, 0.7, 1.0][..], &[][..]));
    // steps over [start, 1]
    let e = evolution(&format!("{BASE}\n[evolution]\nstart = 0.5\nsteps = 2\n"));
    assert_eq!(e.times, [0.75, 1.0]);
}

/// `steps = N`: N equal increments, every table time inside the path inserted (a generated time
/// that close to one replaced by it).
#[test]
fn generated_increments_hit_every_breakpoint() {
    let scene = |evolution: &str| {
        let text = format!("{}\n{evolution}", BASE.edit("part = \"right\"", "part = \"right\"\nname = \"f\""));
        parse(&text).unwrap_or_else(|e| panic!("{e}")).evolution.unwrap()
    };
    // Breakpoints 1, 2.5 and 3 inside [0, 4]; 3 increments at 4/3, 8/3, 4.
    let e = scene("[evolution]\nsteps = 3\n[evolution.factor]\nf = [[0, 0], [1, 1], [2.5, -1], [3, 0], [4, 1]]");
    assert_eq!(e.times, [1.0, 4.0 / 3.0, 2.5, 8.0 / 3.0, 3.0, 4.0]);
    // A breakpoint on a generated time is not repeated: steps = 4 gives 1, 2, 3, 4 with 1 and 3.
    let e = scene("[evolution]\nsteps = 4\n[evolution.factor]\nf = [[0, 0], [1, 1], [3, 0], [4, 1]]");
    assert_eq!(e.times, [1.0, 2.0, 3.0, 4.0]);
    // Starting at 0.1 the generated 0.1 + 0.9·k/9 are not exact tenths: the breakpoints 0.3 and
    // 0.7 replace the generated times next to them, so the path holds them exactly.
    let e = scene("[evolution]\nstart = 0.1\nsteps = 9\n[evolution.factor]\nf = [[0, 0], [0.3, 1], [0.7, -1], [1, 0]]");
    assert_eq!(e.times.len(), 9);
    assert!(e.times.contains(&0.3) && e.times.contains(&0.7), "{:?}", e.times);
    for (k, t) in e.times.iter().enumerate() {
        close(*t, 0.1 + 0.1 * (k + 1) as f64);
    }
    // Breakpoints outside (start, end) are not inserted; start defaults to the first table time.
    let e = scene("[evolution]\nsteps = 2\n[evolution.factor]\nf = [[-1, 0], [1, 1]]");
    assert_eq!((e.start, e.times.as_slice()), (-1.0, &[0.0, 1.0][..]));
    // With listed times nothing is inserted.
    let e = scene("[evolution]\ntimes = [2, 4]\n[evolution.factor]\nf = [[0, 0], [1, 1], [4, 1]]");
    assert_eq!(e.times, [2.0, 4.0]);
    // Several tables: the span is the union, from the earliest first to the latest last time;
    // each table is held constant outside its own times.
    let text = format!(
        "{}\n[evolution]\nsteps = 1\n[evolution.factor]\nf = [[0, 0], [1, 1]]\ng = [[2, 5], [3, 6]]",
        BASE.edit("part = \"right\"", "part = \"right\"\nname = \"f\"")
            .edit("part = \"left\"", "part = \"left\"\nname = \"g\"")
    );
    let e = parse(&text).unwrap().evolution.unwrap();
    assert_eq!(e.times, [1.0, 2.0, 3.0]);
    assert_eq!((e.factor(Some("g"), 1.0), e.factor(Some("f"), 3.0), e.factor(None, 1.5)), (5.0, 1.0, 0.5));
}

#[test]
fn names_without_evolution_change_nothing() {
    let text = BASE.edit("part = \"right\"", "part = \"right\"\nname = \"press\"");
    let s = parse(&format!("{text}\n[contact]\npart = \"bottom\"\nobstacle = \"line\"\npoint = [0, -0.1]\nnormal = [0, 1]\nmotion = [0, 0.05]\n")).unwrap();
    assert_eq!(s.evolution, None);
    assert_eq!(s.tractions[0].name.as_deref(), Some("press"));
    let c = s.contact.unwrap();
    assert_eq!((c.motion, c.name.as_deref()), (Some([0.0, 0.05]), None));
    // applied in full: factor 1
    assert_eq!(c.obstacle_at(1.0), ObstacleSpec::Line { point: [0.0, -0.05], normal: [0.0, 1.0] });
}

// ---- mistakes ---------------------------------------------------------------------------------

/// PRESS_PUSH with one edit: the error is on the line of `needle` (in the edited text).
#[track_caller]
fn error_at(from: &str, to: &str, needle: &str) -> (String, String) {
    let text = PRESS_PUSH.edit(from, to);
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, needle), "{}\n{}", e.message, e.hint);
    (e.message, e.hint)
}

#[test]
fn a_named_load_needs_a_table() {
    let (message, hint) = error_at("weight = [[0, 1], [4, 1]]\n", "", "name = \"weight\"");
    assert_eq!(message, "no table for load `weight` in [evolution.factor]");
    assert!(hint.contains("add `weight = [[0.0, 0.0], [1.0, 1.0]]`") && hint.contains("remove the name"), "{hint}");
    // a near miss: did you mean (the tables are all for known loads)
    let (message, hint) =
        error_at("traction = [1e5, 0.0]", "traction = [1e5, 0.0]\nname = \"pres\"", "name = \"pres\"");
    assert_eq!(message, "no table for load `pres` in [evolution.factor]");
    assert!(hint.contains("did you mean `press`, which has a table?"), "{hint}");
    // a misspelt name on the load: its table is then for an unknown load (checked first)
    let (message, hint) = error_at("name = \"slide\"", "name = \"slid\"", "slide = [[0");
    assert_eq!(message, "a table for an unknown load `slide`");
    assert!(hint.contains("did you mean `slid`?"), "{hint}");
    // no [evolution.factor] at all
    let text =
        format!("{}\n[evolution]\nsteps = 2\n", BASE.edit("part = \"left\"", "part = \"left\"\nname = \"hold\""));
    let e = scene_error(&text);
    assert_eq!(
        (e.line, e.message.as_str()),
        (line_of(&text, "name = \"hold\""), "no table for load `hold` in [evolution.factor]")
    );
}

#[test]
fn a_table_for_an_unknown_load() {
    let (message, hint) = error_at("shear = [[0, 0]", "sheer = [[0, 0]", "sheer = ");
    assert_eq!(message, "a table for an unknown load `sheer`");
    assert!(
        hint.contains("did you mean `shear`?") && hint.contains("the loads are named weight, press, shear, slide"),
        "{hint}"
    );
    // a scene without any named load
    let text = format!("{BASE}\n[evolution]\nsteps = 2\n[evolution.factor]\npress = [[0, 0], [1, 1]]\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "press = "));
    assert!(e.hint.contains("no load of the scene has a name"), "{}", e.hint);
}

#[test]
fn steps_must_be_a_positive_whole_number() {
    for (bad, expected) in [
        ("steps = 0", "`steps` must be at least 1, found 0"),
        ("steps = -3", "`steps` must be at least 1, found -3"),
        ("steps = 2.5", "`steps` must be a whole number, found the number 2.5"),
        ("steps = \"4\"", "`steps` must be a whole number, found the string \"4\""),
        ("steps = 1000000000", "`steps` = 1000000000 is more than 1000000 increments"),
    ] {
        let (message, _) = error_at("steps = 4", bad, bad);
        assert_eq!(message, expected);
    }
}

#[test]
fn steps_or_times_exactly_one() {
    let (message, hint) = error_at("steps = 4", "steps = 4\ntimes = [1, 2]", "times = ");
    assert_eq!(message, "[evolution] gives both `steps` and `times`");
    assert!(hint.contains("keep one"), "{hint}");
    let (message, _) = error_at("steps = 4\n", "", "[evolution]");
    assert_eq!(message, "[evolution] has neither `steps` nor `times`");
    // [evolution.factor] alone: located at its header
    let text = PRESS_PUSH.edit("[evolution]\nsteps = 4\nmonitor = \"top\"\nprofiles = [1.0, 2.0]\n", "");
    let e = scene_error(&text);
    assert_eq!(
        (e.line, e.message.as_str()),
        (line_of(&text, "[evolution.factor]"), "[evolution] has neither `steps` nor `times`")
    );
}

#[test]
fn listed_times_increase_within_the_tables() {
    for (times, expected) in [
        ("times = [1, 3, 2]", "`times` must increase strictly: times[2] = 2 is not after times[1] = 3"),
        ("times = [1, 1]", "`times` must increase strictly: times[1] = 1 is not after times[0] = 1"),
        ("times = [0, 1]", "`times[0]` = 0 is not after the start of the path, 0"),
        ("times = [1, 5]", "`times[1]` = 5 is after the end of the load path, 4"),
        ("times = []", "`times` is empty: the path has no increment"),
        ("times = [1, \"2\"]", "`times[1]` must be a finite number, found the string \"2\""),
        ("times = [1, nan]", "`times[1]` must be a finite number, found the number NaN"),
        ("times = 2", "`times` must be an array of numbers, found the integer 2"),
    ] {
        let (message, _) = error_at("steps = 4", times, "times = ");
        assert_eq!(message, expected, "{times}");
    }
    let (_, hint) = error_at("steps = 4", "times = [1, 5]", "times = ");
    assert!(hint.contains("span [0, 4]") && hint.contains("`press` on line"), "{hint}");
    // without tables the path lies in [0, 1]
    let text = format!("{BASE}\n[evolution]\ntimes = [0.5, 2]\n");
    let e = scene_error(&text);
    assert_eq!(e.message, "`times[1]` = 2 is after the end of the load path, 1");
    assert!(e.hint.contains("without tables"), "{}", e.hint);
}

#[test]
fn start_lies_before_the_end() {
    let (message, hint) = error_at("steps = 4", "steps = 4\nstart = 4", "start = 4");
    assert_eq!(message, "`start` = 4 is not before the end of the load path, 4");
    assert!(hint.contains("[0, 4)"), "{hint}");
    let (message, _) = error_at("steps = 4", "steps = 4\nstart = -1", "start = -1");
    assert_eq!(message, "`start` = -1 is before the beginning of the load path, 0");
    let text = format!("{BASE}\n[evolution]\nsteps = 2\nstart = 1\n");
    let e = scene_error(&text);
    assert_eq!(
        (e.line, e.message.as_str()),
        (line_of(&text, "start = 1"), "`start` = 1 is not before the end of the load path, 1")
    );
    assert!(e.hint.contains("without tables"), "{}", e.hint);
    let (message, _) = error_at("steps = 4", "steps = 4\nstart = \"0\"", "start = ");
    assert!(message.contains("`start` must be a number"), "{message}");
}

#[test]
fn factor_tables_are_checked_row_by_row() {
    for (table, expected) in [
        ("press = [[0, 0], [1, 1], [1, 2], [4, 1]]", "row 3 of the factor table `press` has t = 1, not after row 2's t = 1"),
        ("press = [[0, 0], [2, 1], [1, 1], [4, 1]]", "row 3 of the factor table `press` has t = 1, not after row 2's t = 2"),
        ("press = [[0, 0]]", "the factor table `press` has 1 row: it needs at least 2"),
        ("press = []", "the factor table `press` has 0 rows: it needs at least 2"),
        ("press = [[0, 0], [1, nan], [4, 1]]", "row 2 of the factor table `press` must be [t, factor], two finite numbers, found an array of 2 items [1, nan]"),
        ("press = [[0, 0], [1], [4, 1]]", "row 2 of the factor table `press` must be [t, factor], two finite numbers, found an array of 1 item [1]"),
        ("press = 1.0", "the factor table `press` must be an array of rows [t, factor], found the number 1"),
    ] {
        let (message, _) = error_at("press = [[0, 0], [1, 1], [4, 1]]", table, "press = ");
        assert_eq!(message, expected, "{table}");
    }
    // Tables ending at t ≤ 0: the ramp t / t_end has no meaning.
    let text = format!(
        "{}\n[evolution]\nsteps = 2\n[evolution.factor]\nf = [[-2, 0], [0, 1]]\n",
        BASE.edit("part = \"right\"", "part = \"right\"\nname = \"f\"")
    );
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "f = [[-2"));
    assert!(e.message.contains("end at t = 0"), "{}", e.message);
}

#[test]
fn profiles_are_increment_times() {
    let (message, hint) = error_at("profiles = [1.0, 2.0]", "profiles = [1.0, 2.4]", "profiles = ");
    assert_eq!(message, "`profiles[1]` = 2.4 is not an increment time of the path");
    assert!(hint.contains("the nearest is t = 2 ") && hint.contains("end at 1, 2, 3, 4"), "{hint}");
    let (message, _) = error_at("profiles = [1.0, 2.0]", "profiles = 2.0", "profiles = ");
    assert!(message.contains("`profiles` must be an array of numbers"), "{message}");
    // listed in any order, repeated: sorted, once each
    let text = PRESS_PUSH.edit("profiles = [1.0, 2.0]", "profiles = [4, 2, 4]");
    assert_eq!(evolution(&text).profiles, [2.0, 4.0]);
}

#[test]
fn the_monitor_part_is_checked_against_the_mesh() {
    let text = PRESS_PUSH.edit("monitor = \"top\"", "monitor = \"tpo\"");
    let s = parse(&text).unwrap();
    match s.check_against_mesh(&two_triangles()) {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!(location.line, line_of(&text, "monitor = "));
            assert_eq!(message, "the mesh has no boundary part named `tpo`");
            assert!(hint.contains("did you mean `top`?"), "{hint}");
        }
        other => panic!("{other:?}"),
    }
    let (message, _) = error_at("monitor = \"top\"", "monitor = \"\"", "monitor = ");
    assert_eq!(message, "`monitor` is empty");
}

#[test]
fn names_need_their_load() {
    let (message, hint) = error_at("body_force = [0.0, -1e4]\n", "", "name = \"weight\"");
    assert_eq!(message, "[loads] names its body force, but has no `body_force`");
    assert!(hint.contains("add body_force"), "{hint}");
    let (message, hint) = error_at("motion = [0.01, -0.002]\n", "", "name = \"slide\"");
    assert_eq!(message, "[contact] names the obstacle's motion, but has no `motion`");
    assert!(hint.contains("add motion = [dx, dy]"), "{hint}");
    let (message, _) = error_at("motion = [0.01, -0.002]", "motion = [0.01, inf]", "motion = ");
    assert!(message.contains("`motion` must hold finite numbers"), "{message}");
    let (message, _) = error_at("motion = [0.01, -0.002]", "motion = 0.01", "motion = ");
    assert!(message.contains("`motion` must be an array of two numbers"), "{message}");
    let (message, _) = error_at("name = \"shear\"", "name = \"\"", "name = \"\"");
    assert_eq!(message, "`name` is empty");
    let (message, _) = error_at("name = \"shear\"", "name = 3", "name = 3");
    assert_eq!(message, "`name` must be a string, found the integer 3");
}

#[test]
fn unknown_keys_name_the_evolution_table() {
    let (message, hint) = error_at("steps = 4", "steps = 4\nstep = 4", "step = 4");
    assert_eq!(message, "unknown key `step` in [evolution]");
    assert!(hint.contains("did you mean `steps`?"), "{hint}");
    let (message, hint) = error_at("name = \"shear\"", "nmae = \"shear\"", "nmae = ");
    assert_eq!(message, "unknown key `nmae` in [[traction]]");
    assert!(hint.contains("did you mean `name`?"), "{hint}");
    let (message, hint) = error_at("motion = [0.01", "moton = [0.01", "moton = ");
    assert_eq!(message, "unknown key `moton` in [contact]");
    assert!(hint.contains("did you mean `motion`?"), "{hint}");
}

// ---- several bodies ---------------------------------------------------------------------------

const TWO_BODIES: &str = r#"
[[body]]
name = "punch"
[body.mesh]
shape = "rectangle"
origin = [0.0, 1.0]
size = [1.0, 1.0]
cell_size = 0.5
[body.material]
young = 1e9
poisson = 0.3
[[body.traction]]
part = "top"
pressure = 1e6
name = "press"
[[body]]
name = "base"
[body.mesh]
shape = "rectangle"
size = [1.0, 1.0]
cell_size = 0.5
[body.material]
young = 1e9
poisson = 0.3
[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0
[[contact_pair]]
slave = "punch.bottom"
master = "base.top"
[evolution]
times = [0.5, 1.0]
monitor = "punch.top"
[evolution.factor]
press = [[0, 0], [1, 1]]
"#;

#[test]
fn load_paths_with_several_bodies() {
    let s = parse(TWO_BODIES).unwrap();
    assert_eq!(s.bodies[0].tractions[0].name.as_deref(), Some("press"));
    let e = s.evolution.as_ref().unwrap();
    assert_eq!((e.times.as_slice(), e.monitor.as_deref()), (&[0.5, 1.0][..], Some("punch.top")));
    signorini::scene::BodiesModel::build(&s).unwrap();

    for (monitor, expected) in [
        ("\"punhc.top\"", "`monitor` names an unknown body `punhc`"),
        ("\"top\"", "`monitor` must name a body and one of its boundary parts as \"body.part\", found \"top\""),
    ] {
        let text = TWO_BODIES.edit("\"punch.top\"", monitor);
        let e = scene_error(&text);
        assert_eq!((e.line, e.message.as_str()), (line_of(&text, "monitor = "), expected));
    }
    // the part, once the meshes exist
    let text = TWO_BODIES.edit("\"punch.top\"", "\"punch.tpo\"");
    match signorini::scene::BodiesModel::build(&parse(&text).unwrap()) {
        Err(Error::Scene { location, message, .. }) => {
            assert_eq!(location.line, line_of(&text, "monitor = "));
            assert_eq!(message, "the mesh of body `punch` has no boundary part named `tpo`");
        }
        other => panic!("{other:?}"),
    }
    // a body's named load without a table
    let text = TWO_BODIES.edit("press = [[0, 0], [1, 1]]", "");
    let e = scene_error(&text);
    assert_eq!(
        (e.line, e.message.as_str()),
        (line_of(&text, "name = \"press\""), "no table for load `press` in [evolution.factor]")
    );
}

// ---- the Rust API -----------------------------------------------------------------------------

/// The calls give the path of the scene text; mistakes name the call.
#[test]
fn the_builder_gives_the_load_path_of_a_file() {
    let built = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.25)
        .title("press then push")
        .material(1e9, 0.3)
        .body_force([0.0, -1e4])
        .named("weight")
        .pressure("top", 1e6)
        .named("press")
        .traction("right", [-2e5, 0.0])
        .named("shear")
        .traction("left", [1e5, 0.0])
        .dirichlet_point([0.0, 1.0], Some(1e-4), None)
        .named("press")
        .contact_line("bottom", [0.0, 0.0], [0.0, 1.0])
        .coulomb(0.3)
        .obstacle_motion([0.01, -0.002])
        .named("slide")
        .evolution_steps(4)
        .evolution_monitor("top")
        .evolution_profiles(&[1.0, 2.0])
        .load_factor("press", &[[0.0, 0.0], [1.0, 1.0], [4.0, 1.0]])
        .load_factor("shear", &[[0.0, 0.0], [1.0, 0.0], [2.0, 1.0], [3.0, -1.0], [4.0, 1.0]])
        .load_factor("weight", &[[0.0, 1.0], [4.0, 1.0]])
        .load_factor("slide", &[[0.0, 0.0], [2.0, 0.0], [4.0, 2.5]])
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let read = parse(PRESS_PUSH).unwrap();
    assert_eq!(built.to_toml(), read.to_toml());
    let (b, r) = (built.evolution.clone().unwrap(), read.evolution.clone().unwrap());
    assert_eq!((b.start, &b.times, &b.profiles, &b.monitor), (r.start, &r.times, &r.profiles, &r.monitor));
    assert_eq!(b.at.file, Path::new(BUILT_IN_RUST));
    for t in [0.0, 0.5, 1.0, 2.25, 3.0, 3.9] {
        for name in [None, Some("press"), Some("shear"), Some("weight"), Some("slide")] {
            assert_eq!(b.factor(name, t), r.factor(name, t));
        }
    }
    assert_eq!(
        built.contact.as_ref().map(|c| (c.motion, c.name.clone())),
        Some((Some([0.01, -0.002]), Some("slide".into())))
    );

    // listed times and a start
    let e = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.25)
        .material(1e9, 0.3)
        .pressure("top", 1e6)
        .evolution_times(&[0.5, 1.0])
        .evolution_start(0.25)
        .build()
        .unwrap()
        .evolution
        .unwrap();
    assert_eq!((e.start, e.times.as_slice()), (0.25, &[0.5, 1.0][..]));
}

#[test]
fn builder_mistakes_name_the_call() {
    let block = || SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.25).material(1e9, 0.3);
    let error = |built: signorini::Result<signorini::scene::Scene>| match built {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!(location.file, Path::new(BUILT_IN_RUST));
            (message, hint)
        }
        other => panic!("{other:?}"),
    };
    for (built, expected) in [
        (block().pressure("top", 1.0).named("p").evolution_steps(2), "SceneBuilder::named (`name = \"p\"`): no table for load `p`"),
        (block().evolution_steps(0), "SceneBuilder::evolution_steps (`steps = 0`): `steps` must be at least 1"),
        (block().evolution_times(&[0.5, 0.2]), "SceneBuilder::evolution_times (`times = [0.5, 0.2]`): `times` must increase strictly"),
        (block().evolution_steps(2).evolution_start(2.0), "SceneBuilder::evolution_start (`start = 2.0`)"),
        (block().evolution_steps(2).evolution_profiles(&[0.7]), "SceneBuilder::evolution_profiles (`profiles = [0.7]`): `profiles[0]` = 0.7 is not an increment time"),
        (
            block().pressure("top", 1.0).named("p").evolution_steps(2).load_factor("p", &[[0.0, 0.0], [1.0, 1.0]]).load_factor("q", &[[0.0, 0.0], [1.0, 1.0]]),
            "SceneBuilder::load_factor(\"q\", ..) (`\"q\" = [[0.0, 0.0], [1.0, 1.0]]`): a table for an unknown load `q`",
        ),
        (block().pressure("top", 1.0).named("p").evolution_steps(2).load_factor("p", &[[0.0, 0.0]]), "SceneBuilder::load_factor(\"p\", ..)"),
        (block().pressure("top", 1.0).named(""), "SceneBuilder::named (`name = \"\"`): `name` is empty"),
        (block().contact_line("bottom", [0.0, 0.0], [0.0, 1.0]).obstacle_motion([f64::NAN, 0.0]), "SceneBuilder::obstacle_motion (`motion = [nan, 0.0]`)"),
    ] {
        let (message, _) = error(built.build());
        assert!(message.starts_with(expected), "expected {expected}\n     got {message}");
    }
    // calls that would be ignored, or would replace another
    for (built, expected) in [
        (block().plane_stress().named("x"), "SceneBuilder::named(\"x\"): it names the load of the call just before it, but that call (SceneBuilder::plane_stress) adds no load"),
        (block().pressure("top", 1.0).named("x").named("y"), "SceneBuilder::named(\"y\"): it names the load of the call just before it, but that call (SceneBuilder::named)"),
        (block().obstacle_motion([0.0, 1.0]), "SceneBuilder::obstacle_motion: there is no contact"),
        (block().load_factor("p", &[[0.0, 0.0], [1.0, 1.0]]).evolution_monitor("top"), "SceneBuilder::load_factor, SceneBuilder::evolution_monitor: the load path has no increments"),
        (block().evolution_steps(2).evolution_times(&[1.0]), "SceneBuilder::evolution_times: the list of increments is set twice (by SceneBuilder::evolution_steps before)"),
    ] {
        let (message, _) = error(built.build());
        assert!(message.starts_with(expected), "expected {expected}\n     got {message}");
    }
}

#[test]
fn the_bodies_builder_takes_the_load_path() {
    let punch = SceneBuilder::rectangle([0.0, 1.0], [1.0, 1.0], 0.5)
        .material(1e9, 0.3)
        .pressure("top", 1e6)
        .named("press")
        .build()
        .unwrap();
    let base = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.5)
        .material(1e9, 0.3)
        .dirichlet("bottom", Some(0.0), Some(0.0))
        .build()
        .unwrap();
    let bodies = || {
        BodiesBuilder::new("two").body("punch", punch.clone()).body("base", base.clone()).pair(
            "punch.bottom",
            "base.top",
            FrictionSpec::None,
        )
    };
    let s = bodies()
        .evolution_times(&[0.5, 1.0])
        .evolution_monitor("punch.top")
        .load_factor("press", &[[0.0, 0.0], [1.0, 1.0]])
        .build()
        .unwrap();
    let read = parse(TWO_BODIES).unwrap();
    assert_eq!(
        s.evolution.as_ref().map(|e| (&e.times, &e.monitor)),
        read.evolution.as_ref().map(|e| (&e.times, &e.monitor))
    );
    let message = |b: BodiesBuilder| match b.build() {
        Err(Error::Scene { message, .. }) => message,
        other => panic!("{other:?}"),
    };
    let m = message(bodies().evolution_times(&[1.0]));
    assert!(m.starts_with("BodiesBuilder::body(\"punch\", ..), its SceneBuilder::named (`name = \"press\"`): no table for load `press`"), "{m}");
    let m = message(
        bodies().evolution_times(&[1.0]).evolution_monitor("pnuch.top").load_factor("press", &[[0.0, 0.0], [1.0, 1.0]]),
    );
    assert!(
        m.starts_with("BodiesBuilder::evolution_monitor (`monitor = \"pnuch.top\"`): `monitor` names an unknown body"),
        "{m}"
    );
    let m = message(bodies().evolution_steps(1).evolution_steps(2));
    assert!(m.starts_with("BodiesBuilder::evolution_steps: the setting is given twice"), "{m}");
    let m = message(bodies().load_factor("press", &[[0.0, 0.0], [1.0, 1.0]]));
    assert!(m.starts_with("BodiesBuilder::load_factor: the load path has no increments"), "{m}");
    // a body's scene with its own path is refused
    let with_path =
        SceneBuilder::rectangle([0.0, 1.0], [1.0, 1.0], 0.5).material(1e9, 0.3).evolution_steps(2).build().unwrap();
    let m = message(BodiesBuilder::new("x").body("punch", with_path).body("base", base.clone()));
    assert!(m.contains("a load path"), "{m}");
}

/// A factor multiplies its load in the overflow check: a traction that is fine at factor 1 is
/// refused when its table reaches 1e20 (energy (t L)² / E from 1e249 to 1e289 > 1e280).
#[test]
fn factors_count_in_the_overflow_check() {
    let loaded = BASE.edit("traction = [0.0, -1e6]", "traction = [0.0, -1e130]\nname = \"f\"");
    let mesh = two_triangles();
    for (table, refused) in [("[[0, 0], [1, 1]]", false), ("[[0, 0], [0.5, -1e20], [1, 1]]", true)] {
        let text = format!("{loaded}\n[evolution]\nsteps = 2\n[evolution.factor]\nf = {table}\n");
        let s = parse(&text).unwrap();
        assert_eq!(s.largest_factor(Some("f")), if refused { 1e20 } else { 1.0 });
        match s.check_magnitudes(&mesh) {
            Ok(()) => assert!(!refused, "{table}"),
            Err(Error::Scene { location, message, .. }) => {
                assert!(refused, "{table}: {message}");
                assert_eq!(location.line, line_of(&text, "part = \"right\""));
                assert!(message.contains("would overflow"), "{message}");
            }
            Err(other) => panic!("{other}"),
        }
    }
    // unnamed loads: the ramp, at most 1 at the end of the path; without a path, 1
    let s = parse(&format!("{BASE}\n[evolution]\nsteps = 2\n")).unwrap();
    assert_eq!((s.largest_factor(None), s.largest_factor(Some("absent"))), (1.0, 1.0));
    assert_eq!(parse(BASE).unwrap().largest_factor(Some("x")), 1.0);
}

/// The example of docs/scene-format.md says what its comments say.
#[test]
fn the_documented_load_path_is_what_it_says() {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene-format.md")).unwrap();
    let section = &doc[doc.find("## Load paths: `[evolution]`").unwrap()..];
    let start = section.find("```toml\n").unwrap() + "```toml\n".len();
    let text = &section[start..start + section[start..].find("```").unwrap()];
    let s = parse(text).unwrap_or_else(|e| panic!("{e}"));
    let e = s.evolution.unwrap();
    // 40 increments over [0, 4]: t = k/10, the breakpoints 1, 2, 3 among them
    assert_eq!(e.times.len(), 40);
    for (k, t) in e.times.iter().enumerate() {
        close(*t, (k + 1) as f64 / 10.0);
    }
    assert!([1.0, 2.0, 3.0, 4.0].iter().all(|b| e.times.contains(b)), "{:?}", e.times);
    assert_eq!(e.profiles, [1.0, 2.0, 3.0, 4.0]);
    // press reaches 1 at t = 1 and stays; push starts at t = 1, peaks at 2, reverses to −1 at 3
    assert_eq!((e.factor(Some("press"), 0.5), e.factor(Some("press"), 3.0)), (0.5, 1.0));
    assert_eq!(
        (e.factor(Some("push"), 1.0), e.factor(Some("push"), 2.0), e.factor(Some("push"), 3.0)),
        (0.0, 1.0, -1.0)
    );
    close(e.factor(Some("push"), 2.5), 0.0);
}
