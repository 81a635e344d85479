//! Tests of `sweep_file.rs`.

use super::*;

fn parse(text: &str) -> Result<SweepFile, String> {
    SweepFile::from_str_at(text, Path::new("/nonexistent/test.toml"))
}

#[test]
fn spacing_hits_ends() {
    assert_eq!(linspace(0.0, 0.1, 11)[10], 0.1);
    assert_eq!(linspace(0.0, 0.1, 11)[0], 0.0);
    assert_eq!(linspace(2.0, 3.0, 1), vec![2.0]);
    let l = logspace(300.0, 1e5, 8);
    assert_eq!(l.len(), 8);
    assert_eq!((l[0], l[7]), (300.0, 1e5));
    for w in l.windows(2) {
        assert!((w[1] / w[0] - (1e5f64 / 300.0).powf(1.0 / 7.0)).abs() < 1e-12);
    }
}

#[test]
fn grid_counts_and_name_default() {
    let s = parse(
        "[[axis]]\nkey = \"robot.dead_time\"\nvalues = [0.01, 0.07]\n[[axis]]\nkey = \"module\"\nvalues = [\"hydraulic\", \"bistable\", \"rigid\"]\n",
    )
    .unwrap();
    assert_eq!(s.name, "test");
    assert_eq!(s.n_runs().unwrap(), 6);
    assert_eq!(s.axes[1].kind, AxisKind::Text);
}

#[test]
fn errors_name_the_key() {
    let cases: &[(&str, &str)] = &[
        ("nmae = \"x\"\n", "unknown key `nmae`"),
        ("[[axis]]\nkey = \"robot.dead_tme\"\nvalues = [1]\n", "robot.dead_tme"),
        ("[[axis]]\nkey = \"object.mass\"\nvalues = []\n", "`values` is empty"),
        ("[[axis]]\nkey = \"object.mass\"\nlinspace = [0.1, 1, 0]\n", "n must be an integer >= 1"),
        ("[[axis]]\nkey = \"object.mass\"\nrange = [0.1, 1]\n", "a `range` axis needs sampling mode lhs or sobol, or saltelli"),
        (
            "[sampling]\nmode = \"zip\"\n[[axis]]\nkey = \"object.mass\"\nvalues = [1, 2]\n[[axis]]\nkey = \"robot.dead_time\"\nvalues = [1]\n",
            "zip needs axes of one length",
        ),
        ("[sampling]\nmode = \"lhs\"\n", "needs `samples`"),
        ("[sampling]\nmode = \"sobol\"\nsamples = 100000\n", "at most 65536"),
        ("[sampling]\nmode = \"grid\"\nsamples = 10\n", "`samples` is for lhs, sobol and saltelli only"),
        ("[set]\n\"object.mas\" = 1\n", "object.mas"),
        ("[output]\nrecord = [99]\n", "not a run number"),
        ("name = \"a/b\"\n", "`name`"),
        ("[[axis]]\nkey = \"object.mass\"\nlogspace = [0, 1, 3]\n", "endpoints"),
        ("x = [\n", "line"),
    ];
    for (text, want) in cases {
        let e = parse(text).unwrap_err();
        assert!(e.contains(want), "{text:?}: {e:?} lacks {want:?}");
    }
}

const SALTELLI: &str = "[sampling]\nmode = \"saltelli\"\nsamples = 8\n";

#[test]
fn saltelli_counts_runs() {
    let two = "[[axis]]\nkey = \"robot.dead_time\"\nrange = [0, 0.1]\n[[axis]]\nkey = \"object.mass\"\nrange = [0.05, 1]\n";
    let s = parse(&format!("{SALTELLI}{two}")).unwrap();
    assert_eq!(
        (s.mode, s.second_order, s.n_runs().unwrap()),
        (Mode::Saltelli, true, 8 * 6)
    );
    let s = parse(&format!("{SALTELLI}second_order = false\n{two}")).unwrap();
    assert_eq!(s.n_runs().unwrap(), 8 * 4);
    let s = parse(&format!("{SALTELLI}{two}[sensitivity]\nresamples = 10\n")).unwrap();
    assert!(s.sensitivity.is_some());
}

#[test]
fn distribution_errors_name_the_key() {
    let axis = |body: &str| format!("{SALTELLI}[[axis]]\nkey = \"object.mass\"\n{body}\n");
    let cases: Vec<(String, &str)> = vec![
        (
            axis("dist = \"normal\"\nmean = 0.2\nsd = 0\nrange = [0.1, 1]"),
            "object.mass`): object.mass: sd = 0: must be > 0",
        ),
        (
            axis("dist = \"normal\"\nmean = 0.2\nsd = 0.1"),
            "object.mass must be positive",
        ),
        (
            axis("dist = \"triangular\"\nmode = 2\nrange = [0.1, 1]"),
            "object.mass: mode = 2: must lie in the range [0.1, 1]",
        ),
        (
            axis("dist = \"triangular\"\nmode = 0.5"),
            "dist = \"triangular\" needs `range",
        ),
        (
            axis("dist = \"normal\"\nsd = 0.1"),
            "dist = \"normal\" needs `mean`",
        ),
        (
            axis("dist = \"uniform\"\nsd = 0.1\nrange = [0.1, 1]"),
            "`sd` does not go with dist = \"uniform\"",
        ),
        (
            axis("dist = \"gamma\"\nrange = [0.1, 1]"),
            "dist = \"gamma\": allowed",
        ),
        (
            axis("dist = \"lognormal\"\nmedian = -1\nsigma = 0.3"),
            "median = -1: must be > 0",
        ),
        (
            axis("dist = \"normal\"\nmean = 0.2\nsd = 0.1\nscale = \"log\"\nrange = [0.1, 1]"),
            "do not go together",
        ),
        (
            axis("values = [0.1, 0.2]"),
            "a saltelli sweep takes only `range` axes",
        ),
        (
            axis("values = [0.1, 0.2]\ndist = \"normal\""),
            "`dist` goes with a `range` axis only",
        ),
        (
            format!(
                "{}[[axis]]\nkey = \"object.mass\"\nrange = [0.1, 1]\n",
                SALTELLI.replace("8", "12")
            ),
            "saltelli takes a power of two",
        ),
        (format!("{SALTELLI}second_order = 1\n"), "second_order = 1"),
        (
            "[sampling]\nmode = \"sobol\"\nsamples = 8\nsecond_order = true\n".to_string(),
            "`second_order` is for saltelli only",
        ),
        (SALTELLI.to_string(), "saltelli needs 1 to"),
    ];
    for (text, want) in cases {
        let e = parse(&text).unwrap_err();
        assert!(e.contains(want), "{text:?}: {e:?} lacks {want:?}");
    }
    // A normal may omit its range where the key may be negative, and a lognormal anywhere.
    parse(&axis("dist = \"lognormal\"\nmedian = 0.2\nsigma = 0.3")).unwrap();
}
