//! The Rust types a setting can have, and how each reads from and writes to a
//! [`SettingValue`]: the one place where "a float", "a pair of ints" or "'gpis', 'occupancy'
//! or 'none'" is decided, so the bindings convert nothing by hand.

use super::error::SettingError;
use super::range::Range;
use super::value::SettingValue;

/// A type a setting can have.
pub trait SettingType: Sized {
    /// The Python annotation of the type, e.g. `float | None`.
    const ANNOTATION: &'static str;
    /// The type in words, for errors: e.g. `a float`.
    const EXPECTED: &'static str;

    /// Reads a value given for `key`; [`SettingError::WrongType`] if it has the wrong type
    /// or shape.
    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError>;

    /// The value as the user would type it.
    fn to_value(&self) -> SettingValue;

    /// Checks every number of the value against `range` (and the order of a `(low, high)`
    /// pair).
    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError>;

    /// The strings a choice accepts (empty for other types).
    fn choices() -> &'static [&'static str] {
        &[]
    }

    /// What a value must be, type and range in one phrase, where the range is part of the
    /// type's rule (`an int >= 1` for a count): the message of a value of the wrong type as
    /// of one out of range, so that `10.0` and `0` for a count both state the rule.
    fn rule(_range: &Range) -> Option<String> {
        None
    }
}

fn wrong_type<T: SettingType>(key: &'static str, value: &SettingValue) -> SettingError {
    SettingError::WrongType {
        key,
        expected: T::EXPECTED.to_string(),
        got: value.to_string(),
    }
}

fn in_range(key: &'static str, range: &Range, value: f64) -> Result<(), SettingError> {
    if range.contains(value) {
        Ok(())
    } else if !value.is_finite() {
        Err(SettingError::out_of_range(
            key,
            "finite",
            SettingValue::Float(value),
        ))
    } else {
        Err(SettingError::out_of_range(
            key,
            range.words(),
            SettingValue::Float(value),
        ))
    }
}

fn number(value: &SettingValue) -> Option<f64> {
    match *value {
        SettingValue::Int(v) => Some(v as f64),
        SettingValue::Float(v) => Some(v),
        _ => None,
    }
}

/// The entries of a list of exactly `N` items, each read by `item`.
fn list_of<T: Copy + Default, const N: usize>(
    value: &SettingValue,
    item: fn(&SettingValue) -> Option<T>,
) -> Option<[T; N]> {
    let SettingValue::List(items) = value else {
        return None;
    };
    if items.len() != N {
        return None;
    }
    let mut out = [T::default(); N];
    for (slot, entry) in out.iter_mut().zip(items) {
        *slot = item(entry)?;
    }
    Some(out)
}

fn numbers<const N: usize>(value: &SettingValue) -> Option<[f64; N]> {
    list_of(value, number)
}

fn count(value: &SettingValue) -> Option<usize> {
    match *value {
        SettingValue::Int(v) => usize::try_from(v).ok(),
        _ => None,
    }
}

fn counts<const N: usize>(value: &SettingValue) -> Option<[usize; N]> {
    list_of(value, count)
}

fn ordered(key: &'static str, low: f64, high: f64, strict: bool) -> Result<(), SettingError> {
    if low < high || (!strict && low == high) {
        Ok(())
    } else {
        let relation = if strict { "<" } else { "<=" };
        Err(SettingError::out_of_range(
            key,
            format!("a pair (low, high) with low {relation} high"),
            SettingValue::List(vec![SettingValue::Float(low), SettingValue::Float(high)]),
        ))
    }
}

impl SettingType for f64 {
    const ANNOTATION: &'static str = "float";
    const EXPECTED: &'static str = "a float";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        number(value).ok_or_else(|| wrong_type::<Self>(key, value))
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::Float(*self)
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        in_range(key, range, *self)
    }
}

/// A count's rule, type and range in one phrase: `an int >= 1`.
fn count_rule(range: &Range) -> String {
    format!("an int {}", range.words())
}

impl SettingType for usize {
    const ANNOTATION: &'static str = "int";
    const EXPECTED: &'static str = "a non-negative int";

    fn rule(range: &Range) -> Option<String> {
        Some(count_rule(range))
    }

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        match value {
            SettingValue::Int(v) if *v < 0 => {
                Err(SettingError::out_of_range(key, Self::EXPECTED, value))
            }
            _ => count(value).ok_or_else(|| wrong_type::<Self>(key, value)),
        }
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::Int(i64::try_from(*self).unwrap_or(i64::MAX))
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        if range.contains(*self as f64) {
            Ok(())
        } else {
            Err(SettingError::out_of_range(
                key,
                count_rule(range),
                self.to_value(),
            ))
        }
    }
}

impl SettingType for bool {
    const ANNOTATION: &'static str = "bool";
    const EXPECTED: &'static str = "a bool";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        match *value {
            SettingValue::Bool(v) => Ok(v),
            _ => Err(wrong_type::<Self>(key, value)),
        }
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::Bool(*self)
    }

    fn check(&self, _key: &'static str, _range: &Range) -> Result<(), SettingError> {
        Ok(())
    }
}

/// An optional number: `None` switches the feature off.
impl SettingType for Option<f64> {
    const ANNOTATION: &'static str = "float | None";
    const EXPECTED: &'static str = "a float or None";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        match value {
            SettingValue::Null => Ok(None),
            _ => number(value)
                .map(Some)
                .ok_or_else(|| wrong_type::<Self>(key, value)),
        }
    }

    fn to_value(&self) -> SettingValue {
        self.map_or(SettingValue::Null, SettingValue::Float)
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        self.map_or(Ok(()), |v| in_range(key, range, v))
    }
}

/// A `(low, high)` range of reals: both ends in the setting's range and `low <= high`.
impl SettingType for [f64; 2] {
    const ANNOTATION: &'static str = "tuple[float, float]";
    const EXPECTED: &'static str = "a pair of floats (low, high)";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        numbers::<2>(value).ok_or_else(|| wrong_type::<Self>(key, value))
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::List(self.iter().map(|v| SettingValue::Float(*v)).collect())
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        for &v in self {
            in_range(key, range, v)?;
        }
        ordered(key, self[0], self[1], false)
    }
}

/// A point or direction in space `(x, y, z)` (or a pose `(x, y, yaw)`).
impl SettingType for [f64; 3] {
    const ANNOTATION: &'static str = "tuple[float, float, float]";
    const EXPECTED: &'static str = "a sequence of 3 floats";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        numbers::<3>(value).ok_or_else(|| wrong_type::<Self>(key, value))
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::List(self.iter().map(|v| SettingValue::Float(*v)).collect())
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        self.iter().try_for_each(|&v| in_range(key, range, v))
    }
}

/// A box `((x_min, x_max), (y_min, y_max))`, typed flat as `(x_min, x_max, y_min, y_max)`;
/// each pair strictly increasing.
impl SettingType for [[f64; 2]; 2] {
    const ANNOTATION: &'static str = "tuple[float, float, float, float]";
    const EXPECTED: &'static str = "4 floats (x_min, x_max, y_min, y_max)";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        let [x0, x1, y0, y1] = numbers::<4>(value).ok_or_else(|| wrong_type::<Self>(key, value))?;
        Ok([[x0, x1], [y0, y1]])
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::List(
            self.iter()
                .flatten()
                .map(|v| SettingValue::Float(*v))
                .collect(),
        )
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        for [low, high] in *self {
            in_range(key, range, low)?;
            in_range(key, range, high)?;
            ordered(key, low, high, true)?;
        }
        Ok(())
    }
}

/// A range of counts `(low, high)`, or one count `n` meaning `(n, n)`.
impl SettingType for [usize; 2] {
    const ANNOTATION: &'static str = "int | tuple[int, int]";
    const EXPECTED: &'static str = "an int or a pair of ints (low, high)";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        count(value)
            .map(|n| [n, n])
            .or_else(|| counts::<2>(value))
            .ok_or_else(|| wrong_type::<Self>(key, value))
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::List(self.iter().map(SettingType::to_value).collect())
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        for v in self {
            v.check(key, range)?;
        }
        ordered(key, self[0] as f64, self[1] as f64, false)
    }
}

/// A shape in cells `(rows, columns)`.
impl SettingType for (usize, usize) {
    const ANNOTATION: &'static str = "tuple[int, int]";
    const EXPECTED: &'static str = "a pair of ints (rows, columns)";

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        let [rows, columns] = counts::<2>(value).ok_or_else(|| wrong_type::<Self>(key, value))?;
        Ok((rows, columns))
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::List(vec![self.0.to_value(), self.1.to_value()])
    }

    fn check(&self, key: &'static str, range: &Range) -> Result<(), SettingError> {
        self.0.check(key, range)?;
        self.1.check(key, range)
    }
}

/// A setting that takes one of a few names (an enum).
pub trait Choice: Copy + 'static {
    /// Every accepted name, in order.
    const NAMES: &'static [&'static str];
    /// The Python annotation, e.g. `Literal['gpis', 'occupancy', 'none']`.
    const ANNOTATION: &'static str;
    /// The names in words for errors, e.g. `'gpis', 'occupancy' or 'none'`.
    const EXPECTED: &'static str;
    /// The variant of `NAMES[index]`.
    fn from_index(index: usize) -> Self;
    /// The index of this variant in `NAMES`.
    fn index(self) -> usize;

    /// This variant's name.
    fn name(self) -> &'static str {
        Self::NAMES[self.index()]
    }

    /// The variant called `text`, if any.
    fn parse(text: &str) -> Option<Self> {
        Self::NAMES
            .iter()
            .position(|n| *n == text)
            .map(Self::from_index)
    }
}

/// Implements [`Choice`] for a fieldless enum from one row per variant, `Variant => "name"`:
/// the names, the Python annotation (`Literal['a', 'b']`) and the words of the error
/// (`'a' or 'b'`) are all made from that one list.
#[macro_export]
macro_rules! choice {
    ($ty:ident { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $crate::settings::Choice for $ty {
            const NAMES: &'static [&'static str] = &[$($name),+];
            const ANNOTATION: &'static str =
                concat!("Literal[", $crate::__choice_comma_list!($($name),+), "]");
            const EXPECTED: &'static str = $crate::__choice_or_list!($($name),+);

            fn from_index(index: usize) -> Self {
                [$(Self::$variant),+][index]
            }

            fn index(self) -> usize {
                [$(Self::$variant),+]
                    .iter()
                    .position(|&variant| variant == self)
                    .expect("every variant has a row")
            }
        }
    };
}

/// `'a', 'b', 'c'` from `"a", "b", "c"` (inside the Python `Literal[...]`), for [`crate::choice!`].
#[doc(hidden)]
#[macro_export]
macro_rules! __choice_comma_list {
    ($only:literal) => { concat!("'", $only, "'") };
    ($first:literal, $($rest:literal),+) => {
        concat!("'", $first, "', ", $crate::__choice_comma_list!($($rest),+))
    };
}

/// `'a', 'b' or 'c'` from `"a", "b", "c"` (the words of a choice's error), for [`crate::choice!`].
#[doc(hidden)]
#[macro_export]
macro_rules! __choice_or_list {
    ($only:literal) => { concat!("'", $only, "'") };
    ($first:literal, $last:literal) => { concat!("'", $first, "' or '", $last, "'") };
    ($first:literal, $($rest:literal),+) => {
        concat!("'", $first, "', ", $crate::__choice_or_list!($($rest),+))
    };
}

impl<T: Choice> SettingType for T {
    const ANNOTATION: &'static str = <T as Choice>::ANNOTATION;
    const EXPECTED: &'static str = <T as Choice>::EXPECTED;

    fn from_value(key: &'static str, value: &SettingValue) -> Result<Self, SettingError> {
        match value {
            SettingValue::Text(text) => T::parse(text).ok_or_else(|| {
                SettingError::out_of_range(
                    key,
                    format!("one of {}", <T as Choice>::EXPECTED),
                    value,
                )
            }),
            _ => Err(wrong_type::<Self>(key, value)),
        }
    }

    fn to_value(&self) -> SettingValue {
        SettingValue::Text(self.name().to_owned())
    }

    fn check(&self, _key: &'static str, _range: &Range) -> Result<(), SettingError> {
        Ok(())
    }

    fn choices() -> &'static [&'static str] {
        T::NAMES
    }
}
