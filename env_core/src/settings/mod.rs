//! Settings that describe themselves: each settings struct declares every setting once (the
//! key as the user types it, a doc line, the type, the default and the valid range) with the
//! [`settings!`](crate::settings!) macro, and everything else reads that table: validation,
//! errors that name the user's key, the bindings' keyword arguments and dicts, the Python
//! config class, the docs and the type stub.
//!
//! Adding a setting is one line in one `settings!` block.
//!
//! - [`SettingValue`]: a value as it crosses the boundary (bool, int, float, str, None, list).
//! - [`SettingType`]: the Rust types a setting can have and their conversions.
//! - [`Range`]: the interval a setting's numbers must lie in.
//! - [`SettingError`]: unknown key, wrong type, out of range; each names the key.
//! - [`Checked`]: a config that passed every check, what the core's constructors take.
//! - [`Setting`], [`Settings`]: one row of a table, and a struct that has a table.

mod checked;
mod error;
mod range;
mod setting_type;
mod value;

pub use checked::Checked;
pub use error::SettingError;
pub use range::{Limit, Range, MAX_SCENE_LENGTH};
pub use setting_type::{Choice, SettingType};
pub use value::SettingValue;

type Getter<C> = Box<dyn Fn(&C) -> SettingValue + Send + Sync>;
type Setter<C> = Box<dyn Fn(&mut C, &SettingValue) -> Result<(), SettingError> + Send + Sync>;
type Checker<C> = Box<dyn Fn(&C) -> Result<(), SettingError> + Send + Sync>;

/// One setting of the config struct `C`: what the user sees of it, and how to read, write
/// and check it.
pub struct Setting<C> {
    /// The key as the user types it (unique across every table).
    pub key: &'static str,
    /// What the setting means, with its unit.
    pub doc: &'static str,
    /// The Python annotation of its type.
    pub annotation: &'static str,
    /// The names a choice accepts (empty for other types).
    pub choices: &'static [&'static str],
    /// The interval its numbers must lie in.
    pub range: Range,
    get: Getter<C>,
    set: Setter<C>,
    check: Checker<C>,
}

impl<C: 'static> Setting<C> {
    /// The setting `key` stored in the field that `field`/`field_mut` reach.
    pub fn field<T: SettingType + 'static>(
        key: &'static str,
        doc: &'static str,
        range: Range,
        field: fn(&C) -> &T,
        field_mut: fn(&mut C) -> &mut T,
    ) -> Self {
        Self {
            key,
            doc,
            annotation: T::ANNOTATION,
            choices: T::choices(),
            range,
            get: Box::new(move |c| field(c).to_value()),
            set: Box::new(move |c, value| {
                *field_mut(c) =
                    T::from_value(key, value).map_err(|e| e.with_rule(T::rule(&range)))?;
                Ok(())
            }),
            check: Box::new(move |c| field(c).check(key, &range)),
        }
    }

    /// This setting of a part `C` of a bigger config `P` (a section such as the cupboard
    /// within the scene), reached through `part`/`part_mut`.
    pub fn lifted<P: 'static>(
        &'static self,
        part: fn(&P) -> &C,
        part_mut: fn(&mut P) -> &mut C,
    ) -> Setting<P> {
        Setting {
            key: self.key,
            doc: self.doc,
            annotation: self.annotation,
            choices: self.choices,
            range: self.range,
            get: Box::new(move |p| (self.get)(part(p))),
            set: Box::new(move |p, value| (self.set)(part_mut(p), value)),
            check: Box::new(move |p| (self.check)(part(p))),
        }
    }

    /// The current value in `config`.
    pub fn get(&self, config: &C) -> SettingValue {
        (self.get)(config)
    }

    /// Writes `value` into `config`; fails if it has the wrong type (ranges are checked by
    /// [`Settings::check_settings`]).
    pub fn set(&self, config: &mut C, value: &SettingValue) -> Result<(), SettingError> {
        (self.set)(config, value)
    }

    /// Checks the value in `config` against this setting's range.
    pub fn check(&self, config: &C) -> Result<(), SettingError> {
        (self.check)(config)
    }
}

/// A config struct with a settings table (implemented by [`settings!`](crate::settings!)).
pub trait Settings: Default + 'static {
    /// Every setting, sections included, in declaration order.
    fn table() -> &'static [Setting<Self>];

    /// Checks that involve several settings (beyond each one's range), sections first.
    fn check_across(&self) -> Result<(), SettingError>;

    /// Checks every setting against its range, then across settings; the first failure is
    /// reported. Cost: O(settings).
    fn check_settings(&self) -> Result<(), SettingError> {
        for setting in Self::table() {
            setting.check(self)?;
        }
        self.check_across()
    }

    /// The setting called `key`.
    fn setting(key: &str) -> Result<&'static Setting<Self>, SettingError> {
        Self::table()
            .iter()
            .find(|s| s.key == key)
            .ok_or_else(|| SettingError::unknown_key(key, &Self::keys()))
    }

    /// Every key, in declaration order.
    fn keys() -> Vec<&'static str> {
        Self::table().iter().map(|s| s.key).collect()
    }

    /// Writes `value` to the setting `key` (type checked; ranges by [`Self::check_settings`]).
    fn set_value(&mut self, key: &str, value: &SettingValue) -> Result<(), SettingError> {
        Self::setting(key)?.set(self, value)
    }

    /// The value of the setting `key`.
    fn get_value(&self, key: &str) -> Result<SettingValue, SettingError> {
        Ok(Self::setting(key)?.get(self))
    }

    /// Every `(key, value)`, in declaration order.
    fn to_pairs(&self) -> Vec<(&'static str, SettingValue)> {
        Self::table().iter().map(|s| (s.key, s.get(self))).collect()
    }

    /// The defaults with `pairs` written over them, checked: the one place a config made
    /// from outside the core is checked.
    ///
    /// # Errors
    /// An unknown key, a value of the wrong type, or the first setting or relation out of
    /// range, named by its key.
    fn from_pairs<'a>(
        pairs: impl IntoIterator<Item = (&'a str, SettingValue)>,
    ) -> Result<Checked<Self>, SettingError> {
        // Every key first, as Python refuses an unexpected keyword before it reads values.
        let pairs: Vec<(&str, SettingValue)> = pairs.into_iter().collect();
        let settings = pairs
            .iter()
            .map(|(key, _)| Self::setting(key))
            .collect::<Result<Vec<_>, _>>()?;
        let mut config = Self::default();
        for (setting, (_, value)) in settings.into_iter().zip(&pairs) {
            setting.set(&mut config, value)?;
        }
        Checked::new(config)
    }

    /// This config, checked ([`Checked::new`]).
    fn checked(self) -> Result<Checked<Self>, SettingError> {
        Checked::new(self)
    }
}

impl<C: Settings> Checked<C> {
    /// Checks `config`.
    ///
    /// # Cost
    /// O(settings).
    ///
    /// # Errors
    /// The first setting out of its range, or the first relation between settings broken,
    /// named by its key ([`SettingError`]).
    pub fn new(config: C) -> Result<Self, SettingError> {
        config.check_settings()?;
        Ok(Self::wrap(config))
    }

    /// The section `part` of this config, checked: a config's check covers its sections
    /// (the `settings!` table lifts every section's settings and runs its relations), so
    /// the section needs no check of its own.
    ///
    /// # Cost
    /// One clone of the section.
    pub fn section<S: Settings + Clone>(&self, part: impl FnOnce(&C) -> &S) -> Checked<S> {
        Checked::wrap(part(self).clone())
    }
}

/// Declares a config struct and its settings table at once.
///
/// ```ignore
/// settings! {
///     /// The shelf compartment.
///     pub struct CupboardConfig {
///         /// Interior width along x, m.
///         width: f64 = 0.60 => "cupboard_width" in Range::POSITIVE,
///     }
///     sections {}
///     check_across = |_config| Ok(());
/// }
/// ```
///
/// Each field becomes a documented `pub` field, its default goes into `Default`, and its
/// key, doc, type and range into [`Settings::table`]. Sections are nested configs whose
/// settings are lifted into this table (their keys must stay unique); `check_across` checks
/// relations between settings after each one's range.
#[macro_export]
macro_rules! settings {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(
                $(#[doc = $doc:literal])+
                $field:ident : $ty:ty = $default:expr => $key:literal in $range:expr
            ),* $(,)?
        }
        sections {
            $(
                $(#[doc = $section_doc:literal])+
                $section:ident : $section_ty:ty
            ),* $(,)?
        }
        check_across = $check:expr;
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, PartialEq)]
        pub struct $name {
            $(
                $(#[doc = $doc])+
                pub $field: $ty,
            )*
            $(
                $(#[doc = $section_doc])+
                pub $section: $section_ty,
            )*
        }

        impl Default for $name {
            fn default() -> Self {
                Self {
                    $($field: $default,)*
                    $($section: <$section_ty>::default(),)*
                }
            }
        }

        impl $crate::settings::Settings for $name {
            fn table() -> &'static [$crate::settings::Setting<Self>] {
                static TABLE: std::sync::OnceLock<Vec<$crate::settings::Setting<$name>>> =
                    std::sync::OnceLock::new();
                TABLE.get_or_init(|| {
                    #[allow(unused_mut)]
                    let mut table: Vec<$crate::settings::Setting<$name>> = vec![
                        $(
                            $crate::settings::Setting::field::<$ty>(
                                $key,
                                concat!($($doc),+).trim_start(),
                                $range,
                                |c: &$name| &c.$field,
                                |c: &mut $name| &mut c.$field,
                            ),
                        )*
                    ];
                    $(
                        for setting in <$section_ty as $crate::settings::Settings>::table() {
                            table.push(setting.lifted(
                                |c: &$name| &c.$section,
                                |c: &mut $name| &mut c.$section,
                            ));
                        }
                    )*
                    table
                })
            }

            fn check_across(&self) -> Result<(), $crate::settings::SettingError> {
                $(
                    <$section_ty as $crate::settings::Settings>::check_across(&self.$section)?;
                )*
                let check: fn(&$name) -> Result<(), $crate::settings::SettingError> = $check;
                check(self)
            }
        }
    };
}
