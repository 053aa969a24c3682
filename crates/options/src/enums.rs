//! An enum option's values by position: the table stores a choice as its
//! index, and the command line spells it with clap's names.

use clap::ValueEnum;
use clap::builder::PossibleValue;

/// The position of `x` among its enum's values.
pub fn index_of<T: ValueEnum + PartialEq>(x: T) -> usize {
    T::value_variants()
        .iter()
        .position(|v| *v == x)
        .unwrap_or(0)
}

/// The enum's value at position `i` (the default past the end).
pub fn variant<T: ValueEnum + Copy + Default>(i: usize) -> T {
    T::value_variants().get(i).copied().unwrap_or_default()
}

/// The command line's spellings of an enum's values, with their help.
pub fn values<T: ValueEnum>() -> Vec<PossibleValue> {
    T::value_variants()
        .iter()
        .filter_map(ValueEnum::to_possible_value)
        .collect()
}
