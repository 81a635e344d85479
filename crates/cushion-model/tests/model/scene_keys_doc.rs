//! `docs/scene-keys.md` holds the table of every scene key (key, default, unit, description),
//! generated from `Scene::key_info()` and `Scene::default()`. The test fails when the page and
//! the code differ, so the page cannot go stale; after changing a key's unit, description or
//! default,
//!
//! ```text
//! CUSHION_BLESS=1 cargo test -p cushion-model --test model scene_keys_doc
//! ```
//!
//! rewrites the table between the page's two marker comments (the text around it is left as it
//! is).

use std::path::PathBuf;

use cushion_model::{ConfigError, KeyInfo, Scene};

const BEGIN: &str = "<!-- BEGIN scene-keys table: generated from Scene::key_info(); \
                     CUSHION_BLESS=1 cargo test -p cushion-model --test model scene_keys_doc rewrites it -->";
const END: &str = "<!-- END scene-keys table -->";

/// The units a key may have: SI, `-` for a dimensionless number, `""` for a choice of words, a
/// switch, or `solver.atol` (every state in its own unit).
const UNITS: &[&str] = &[
    "",
    "-",
    "s",
    "m",
    "m/s",
    "m/s^2",
    "m^3",
    "kg",
    "kg/s",
    "kg/m^3",
    "m^2/s",
    "N",
    "N/m",
    "N/m^1.5",
    "N s/m^2.5",
    "Pa",
];

fn doc_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-keys.md")
}

/// A default as a TOML value a user can type, readable at a glance: floats of magnitude 1e5 and
/// more or below 1e-3 in exponent form (`1.35e6`, `7.63e-5`), large integers with `_` between
/// thousands (`1_000_000`); anything else as TOML writes it (strings quoted).
fn toml_text(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(x) if *x != 0.0 && (x.abs() >= 1e5 || x.abs() < 1e-3) => {
            format!("{x:e}")
        }
        toml::Value::Integer(n) if n.abs() >= 100_000 => {
            let digits = n.unsigned_abs().to_string();
            let mut out = String::new();
            for (i, c) in digits.chars().enumerate() {
                if i > 0 && (digits.len() - i) % 3 == 0 {
                    out.push('_');
                }
                out.push(c);
            }
            if *n < 0 {
                out.insert(0, '-');
            }
            out
        }
        _ => v.to_string(),
    }
}

/// The table as the page holds it: one row per key, in the order of `Scene::keys()`, defaults
/// as TOML values (strings quoted; see `toml_text`).
fn table() -> String {
    let scene = Scene::default();
    let mut t = String::from(
        "| key | default (hydraulic scene) | unit | description |\n|---|---|---|---|\n",
    );
    for KeyInfo {
        key,
        unit,
        description,
    } in Scene::key_info()
    {
        let value = scene.get(key).expect("every key has a value");
        let default = toml_text(&value);
        t.push_str(&format!(
            "| `{key}` | `{default}` | {unit} | {description} |\n"
        ));
    }
    t
}

/// The page's text between the markers, and where it starts and ends.
fn generated_part(page: &str) -> Option<(usize, usize)> {
    let start = page.find(BEGIN)? + BEGIN.len();
    let end = start + page[start..].find(END)?;
    (page.matches(BEGIN).count() == 1 && page.matches(END).count() == 1).then_some((start, end))
}

#[test]
fn doc_page_holds_the_table_of_the_code() {
    let path = doc_path();
    let page = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let (start, end) = generated_part(&page).unwrap_or_else(|| {
        panic!(
            "{} must hold the lines\n{BEGIN}\n{END}\nonce each, the table between them",
            path.display()
        )
    });
    // blank lines around the table keep it a table in every Markdown reader
    let wanted = format!("\n\n{}\n", table());
    if std::env::var("CUSHION_BLESS").is_ok_and(|v| v == "1") {
        let new = format!("{}{wanted}{}", &page[..start], &page[end..]);
        if new != page {
            std::fs::write(&path, new)
                .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        }
        return;
    }
    assert!(
        page[start..end] == wanted,
        "{} is stale: its table differs from Scene::key_info() and the defaults; \
         run `CUSHION_BLESS=1 cargo test -p cushion-model --test model scene_keys_doc` to rewrite it.\n\
         expected:\n{wanted}\nfound:\n{}",
        path.display(),
        &page[start..end]
    );
}

#[test]
fn key_info_lists_every_key_in_order() {
    let info: Vec<&str> = Scene::key_info().iter().map(|i| i.key).collect();
    assert_eq!(info, Scene::keys());
}

#[test]
fn every_key_has_a_one_line_description_and_a_known_unit() {
    let scene = Scene::default();
    for info in Scene::key_info() {
        let d = info.description;
        assert!(!d.trim().is_empty(), "`{}` has no description", info.key);
        assert!(
            !d.contains(['\n', '|']) && d.trim() == d,
            "`{}`: the description must be one table cell: {d:?}",
            info.key
        );
        assert!(
            UNITS.contains(&info.unit),
            "`{}`: unit {:?} is not one of {UNITS:?}",
            info.key,
            info.unit
        );
        // a number has a unit ("-" when dimensionless); words and switches have none
        match scene.get(info.key).unwrap() {
            toml::Value::Float(_) | toml::Value::Integer(_) if info.key != "solver.atol" => {
                assert!(!info.unit.is_empty(), "`{}` is a number", info.key)
            }
            toml::Value::String(_) | toml::Value::Boolean(_) => {
                assert_eq!(info.unit, "", "`{}` is a choice or a switch", info.key)
            }
            _ => {}
        }
    }
}

#[test]
fn choice_keys_name_every_allowed_value() {
    let scene = Scene::default();
    for info in Scene::key_info() {
        if !matches!(scene.get(info.key).unwrap(), toml::Value::String(_)) {
            continue;
        }
        // the parser's own list of names, from its refusal of a name it does not know
        let mut s = Scene::default();
        let allowed = match s.set(info.key, &toml::Value::String("no-such-name".into())) {
            Err(ConfigError::InvalidValue { allowed, .. }) => allowed,
            other => panic!("`{}`: {other:?}", info.key),
        };
        let names: Vec<&str> = allowed.split('"').skip(1).step_by(2).collect();
        assert!(!names.is_empty(), "`{}`: {allowed}", info.key);
        for name in names {
            assert!(
                info.description.contains(&format!("\"{name}\"")),
                "`{}`: the description does not name \"{name}\": {}",
                info.key,
                info.description
            );
        }
    }
}

#[test]
fn the_page_s_defaults_read_back_as_the_code_s() {
    let scene = Scene::default();
    for KeyInfo { key, .. } in Scene::key_info() {
        let value = scene.get(key).expect("every key has a value");
        let text = toml_text(&value);
        let read: toml::Table = toml::from_str(&format!("x = {text}")).expect("a TOML value");
        assert_eq!(read["x"], value, "{key}: {text}");
    }
}
