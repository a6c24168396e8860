//! File formats of other tools read into moorfret's own: MoorDyn v2 input decks
//! ([`moordyn`]).

pub mod moordyn;
