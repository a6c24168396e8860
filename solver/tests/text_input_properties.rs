//! Adversarial text inputs. MoorDyn decks: the example deck of the paper's line with one token
//! replaced, a row deleted or a row repeated; the import never panics, it refuses with a message
//! naming a deck row (or the deck) or returns a case that validates. Scatter tables of arbitrary
//! digits and separators: parsed or refused, never a panic.

use moorfret_solver::global::case::FloaterSource;
use moorfret_solver::io::moordyn::{import, ImportSettings};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

const DECK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/examples/moordyn/paper_line.dat"
));

fn settings() -> ImportSettings {
    ImportSettings {
        name: "fuzz".into(),
        floater: FloaterSource::PrescribedMotion {
            csv_path: "surge.csv".into(),
        },
        time_step_s: 0.1,
        duration_s: 10.0,
        hot_spots: vec![],
    }
}

#[derive(Debug, Clone)]
enum Edit {
    Token(usize, usize, &'static str),
    Delete(usize),
    Repeat(usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let token = prop::sample::select(vec![
        "0",
        "-1",
        "1e300",
        "-1e300",
        "1e-300",
        "nan",
        "inf",
        "R1A",
        "x",
        "999",
        "4294967296",
        "0.5",
        "Free",
        "Fixed",
        "Coupled",
        "Body1",
        "---- LINES ----",
        "!",
        "1|2",
    ]);
    prop_oneof![
        (0..60_usize, 0..12_usize, token).prop_map(|(r, c, t)| Edit::Token(r, c, t)),
        (0..60_usize).prop_map(Edit::Delete),
        (0..60_usize).prop_map(Edit::Repeat),
    ]
}

fn apply(e: &Edit) -> String {
    let mut rows: Vec<String> = DECK.lines().map(str::to_owned).collect();
    let n = rows.len();
    match *e {
        Edit::Token(r, c, t) => {
            let row = &mut rows[r % n];
            let mut tokens: Vec<String> = row.split_whitespace().map(str::to_owned).collect();
            if tokens.is_empty() {
                *row = t.to_owned();
            } else {
                let k = c % tokens.len();
                tokens[k] = t.to_owned();
                *row = tokens.join(" ");
            }
        }
        Edit::Delete(r) => {
            rows.remove(r % n);
        }
        Edit::Repeat(r) => {
            let row = rows[r % n].clone();
            rows.insert(r % n, row);
        }
    }
    rows.join("\n") + "\n"
}

proptest! {
    #![proptest_config(Config {
        cases: 400,
        rng_seed: RngSeed::Fixed(20261126),
        failure_persistence: None,
        ..Config::default()
    })]

    #[test]
    fn an_edited_deck_is_refused_by_row_or_imported_valid(e in edit()) {
        let deck = apply(&e);
        match import(&deck, &settings()) {
            Ok(imported) => prop_assert_eq!(imported.case.validate(), Ok(())),
            Err(err) => {
                let text = err.to_string();
                prop_assert!(
                    text.starts_with("deck row ") || err.row == 0,
                    "{e:?}: {text}"
                );
                prop_assert!(err.row <= deck.lines().count(), "{e:?}: {text}");
            }
        }
    }

    /// Scatter tables of arbitrary digits, separators and signs parse or are refused; never a
    /// panic.
    #[test]
    fn arbitrary_scatter_text_never_panics(text in "[0-9eE\t ,;.+-]{0,40}(\n[0-9eE\t ,;.+-]{0,40}){0,8}") {
        let _ = moorfret_solver::waves::scatter::ScatterTable::parse(&text);
    }
}
