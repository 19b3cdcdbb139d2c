//! Writing typed records as CSV: the one place a header is tied to its fields and a number is
//! formatted.
//!
//! A record kind is a `serde::Serialize` struct whose fields, in order, are its columns
//! ([`CsvRecord::HEADER`] names them; a test checks the names against the serde field names).
//! Real numbers are written by [`fmt_real`] (the shortest text that reads back to the same
//! `f64`; `inf`, `-inf`, `NaN`) through the field adapters [`real`], [`real_or_empty`] (NaN →
//! empty field), [`opt_real`] (`None` → empty field) and, for error estimates, [`real_exp`]
//! (exponent notation). Text fields are quoted only when they
//! hold a comma, a quote or a line break (RFC 4180, the `csv` crate's rule), so every file
//! reads back with any CSV reader.
//!
//! Whole files: [`to_csv`]. One row as fields (what the sweep driver stores, checkpoints and
//! merges): [`fields`].
//!
//! ```
//! use helixreach::records::{csv_out, SpeedErrorRow};
//! let rows = [SpeedErrorRow {
//!     method: "continuum".into(),
//!     resolution: "tol=1e-8".into(),
//!     time_per_direction_s: 2.5e-5,
//!     max_rel_err: 1e-9,
//!     median_rel_err: 0.0,
//! }];
//! assert_eq!(
//!     csv_out::to_csv(&rows)?,
//!     "method,resolution,time_per_direction_s,max_rel_err,median_rel_err\n\
//!      continuum,tol=1e-8,0.000025,0.000000001,0\n"
//! );
//! # Ok::<(), helixreach::Error>(())
//! ```

use super::fmt_real;
use crate::error::{Error, Result};
use crate::math::Real;
use serde::Serialize;

/// A record kind written as CSV: a serde struct whose fields are the columns of [`Self::HEADER`],
/// in order.
pub trait CsvRecord: Serialize {
    /// The column names, in field order.
    const HEADER: &'static [&'static str];
}

fn ser_error(e: impl std::fmt::Display) -> Error {
    Error::invalid("csv record", "", e.to_string())
}

/// The CSV text of `rows` under `header` (written even when `rows` is empty).
pub fn to_csv_with<R: Serialize>(header: &[&str], rows: &[R]) -> Result<String> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.write_record(header).map_err(ser_error)?;
    for r in rows {
        w.serialize(r).map_err(ser_error)?;
    }
    let bytes = w.into_inner().map_err(ser_error)?;
    String::from_utf8(bytes).map_err(ser_error)
}

/// The CSV text of `rows`: [`CsvRecord::HEADER`], then one line per row.
pub fn to_csv<R: CsvRecord>(rows: &[R]) -> Result<String> {
    to_csv_with(R::HEADER, rows)
}

/// Rows written one at a time to `W` (a large or unbounded output, e.g. stdout): the header
/// first, then each row as [`to_csv`] writes it.
pub struct CsvStream<W: std::io::Write> {
    w: csv::Writer<W>,
}

impl<W: std::io::Write> std::fmt::Debug for CsvStream<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CsvStream").finish_non_exhaustive()
    }
}

impl<W: std::io::Write> CsvStream<W> {
    /// Start a stream: write `header`.
    pub fn new(out: W, header: &[&str]) -> Result<Self> {
        let mut w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(out);
        w.write_record(header).map_err(ser_error)?;
        Ok(CsvStream { w })
    }

    /// Write one row.
    pub fn write<R: Serialize>(&mut self, row: &R) -> Result<()> {
        self.w.serialize(row).map_err(ser_error)
    }

    /// Flush and give back the writer.
    pub fn finish(self) -> Result<W> {
        self.w.into_inner().map_err(ser_error)
    }
}

/// Field adapter: a real in exponent notation with 16 digits after the point (`{:.16e}`, 17
/// significant digits: round-trips, and every row has the same width).
pub fn real_e16<S: serde::Serializer>(x: &Real, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{x:.16e}"))
}

/// One record as its fields' text (the sweep driver's row), formatted as [`to_csv`] writes them.
pub fn fields<R: Serialize>(r: &R) -> Result<Vec<String>> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.serialize(r).map_err(ser_error)?;
    let bytes = w.into_inner().map_err(ser_error)?;
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(bytes.as_slice());
    let rec = rd
        .records()
        .next()
        .ok_or_else(|| ser_error("a record serialized to no row"))?
        .map_err(ser_error)?;
    Ok(rec.iter().map(str::to_string).collect())
}

/// The column names of `r` in order (to check a [`CsvRecord::HEADER`]): its serde field names,
/// a nested struct's names in its place (where the csv writer puts its values).
pub fn field_names<R: Serialize>(r: &R) -> Result<Vec<String>> {
    let mut n = names::Names::default();
    r.serialize(&mut n).map_err(ser_error)?;
    Ok(n.names)
}

/// A serializer that records field names instead of values (the csv crate's header writer
/// refuses nested structs, its row writer writes their fields in place).
mod names {
    use serde::ser::{self, Impossible, Serialize};

    #[derive(Debug)]
    pub struct NamesError(String);

    impl std::fmt::Display for NamesError {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str(&self.0)
        }
    }

    impl std::error::Error for NamesError {}

    impl ser::Error for NamesError {
        fn custom<T: std::fmt::Display>(msg: T) -> Self {
            NamesError(msg.to_string())
        }
    }

    type Res = Result<(), NamesError>;
    type No = Impossible<(), NamesError>;

    /// The names seen so far, and the field whose value is being serialized.
    #[derive(Debug, Default)]
    pub struct Names {
        pub names: Vec<String>,
        key: Option<&'static str>,
    }

    impl Names {
        /// A value with one column: the current field's name.
        fn leaf(&mut self) -> Res {
            let k = self
                .key
                .take()
                .ok_or_else(|| not_a_column("a value outside a struct"))?;
            self.names.push(k.to_string());
            Ok(())
        }
    }

    fn not_a_column(what: &str) -> NamesError {
        NamesError(format!(
            "{what} has no column name (give the header to to_csv_with)"
        ))
    }

    macro_rules! leaves {
        ($($f:ident: $t:ty),*) => {
            $(fn $f(self, _: $t) -> Res { self.leaf() })*
        };
    }

    impl ser::Serializer for &mut Names {
        type Ok = ();
        type Error = NamesError;
        type SerializeSeq = No;
        type SerializeTuple = No;
        type SerializeTupleStruct = No;
        type SerializeTupleVariant = No;
        type SerializeMap = No;
        type SerializeStruct = Self;
        type SerializeStructVariant = No;

        leaves!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
            serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32,
            serialize_u64: u64, serialize_f32: f32, serialize_f64: f64, serialize_char: char,
            serialize_str: &str, serialize_bytes: &[u8], serialize_unit_struct: &'static str);

        fn serialize_none(self) -> Res {
            self.leaf()
        }
        fn serialize_some<T: ?Sized + Serialize>(self, v: &T) -> Res {
            v.serialize(self)
        }
        fn serialize_unit(self) -> Res {
            self.leaf()
        }
        fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Res {
            self.leaf()
        }
        fn serialize_newtype_struct<T: ?Sized + Serialize>(self, _: &'static str, v: &T) -> Res {
            v.serialize(self)
        }
        fn serialize_newtype_variant<T: ?Sized + Serialize>(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: &T,
        ) -> Res {
            self.leaf()
        }
        fn serialize_seq(self, _: Option<usize>) -> Result<No, NamesError> {
            Err(not_a_column("a sequence"))
        }
        fn serialize_tuple(self, _: usize) -> Result<No, NamesError> {
            Err(not_a_column("a tuple"))
        }
        fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<No, NamesError> {
            Err(not_a_column("a tuple struct"))
        }
        fn serialize_tuple_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: usize,
        ) -> Result<No, NamesError> {
            Err(not_a_column("a tuple variant"))
        }
        fn serialize_map(self, _: Option<usize>) -> Result<No, NamesError> {
            Err(not_a_column("a map"))
        }
        fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, NamesError> {
            // A nested struct: its fields name the columns, not the field holding it.
            self.key = None;
            Ok(self)
        }
        fn serialize_struct_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: usize,
        ) -> Result<No, NamesError> {
            Err(not_a_column("a struct variant"))
        }
    }

    impl ser::SerializeStruct for &mut Names {
        type Ok = ();
        type Error = NamesError;
        fn serialize_field<T: ?Sized + Serialize>(&mut self, key: &'static str, v: &T) -> Res {
            self.key = Some(key);
            v.serialize(&mut **self)
        }
        fn end(self) -> Res {
            Ok(())
        }
    }
}

/// Field adapter: a real by [`fmt_real`] (`#[serde(serialize_with = "csv_out::real")]`).
pub fn real<S: serde::Serializer>(x: &Real, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&fmt_real(*x))
}

/// Field adapter: every real of a slice by [`fmt_real`], one field each (a variable number of
/// columns, e.g. one per joint; the header then comes from [`to_csv_with`]).
pub fn reals<S: serde::Serializer>(x: &&[Real], s: S) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(x.len()))?;
    for v in x.iter() {
        seq.serialize_element(&fmt_real(*v))?;
    }
    seq.end()
}

/// Field adapter: a real in exponent notation (`1.5e-9`, `0e0`), for error estimates.
pub fn real_exp<S: serde::Serializer>(x: &Real, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{x:e}"))
}

/// Field adapter: [`real_exp`], NaN (not computed) as an empty field.
pub fn real_exp_or_empty<S: serde::Serializer>(
    x: &Real,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    if x.is_nan() {
        s.serialize_str("")
    } else {
        real_exp(x, s)
    }
}

/// Field adapter: a real by [`fmt_real`], NaN (not computed) as an empty field.
pub fn real_or_empty<S: serde::Serializer>(x: &Real, s: S) -> std::result::Result<S::Ok, S::Error> {
    if x.is_nan() {
        s.serialize_str("")
    } else {
        real(x, s)
    }
}

/// Field adapter: `Some(x)` by [`fmt_real`], `None` as an empty field.
pub fn opt_real<S: serde::Serializer>(
    x: &Option<Real>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    match x {
        Some(v) => real(v, s),
        None => s.serialize_str(""),
    }
}

/// Test helper: `R::HEADER` names `r`'s serde fields in order, one field per column.
#[cfg(test)]
pub(crate) fn header_matches<R: CsvRecord>(r: &R) {
    assert_eq!(field_names(r).unwrap(), R::HEADER, "header vs serde fields");
    assert_eq!(fields(r).unwrap().len(), R::HEADER.len());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::bifurcation::BifurcationRecord;
    use crate::records::compare::ComparisonRecord;
    use crate::records::series::{PhasedSeriesRecord, SeriesRecord};
    use crate::records::{DirColumns, SpeedErrorRow};

    use super::header_matches;

    fn series() -> SeriesRecord {
        SeriesRecord {
            t: 0.1,
            s: 1.0 / 3.0,
            kappa: 2.5e-17,
            tau: -7.0,
            omega: 1e300,
            error: Real::NAN,
            energy: Real::INFINITY,
        }
    }

    /// Every record kind's header names its serde fields, in order.
    #[test]
    fn headers_name_the_fields_in_order() {
        header_matches(&series());
        // A nested record: the sample's columns in place, then the phase.
        let phased = PhasedSeriesRecord {
            sample: series(),
            phase: "unload",
        };
        header_matches(&phased);
        assert_eq!(
            fields(&phased).unwrap(),
            [fields(&series()).unwrap(), vec!["unload".into()]].concat()
        );
        header_matches(&SpeedErrorRow {
            method: "der".into(),
            resolution: "n=100".into(),
            time_per_direction_s: 1.0,
            max_rel_err: 0.0,
            median_rel_err: 0.0,
        });
        header_matches(&ComparisonRecord {
            dir: DirColumns {
                dir_kappa: 1.0,
                dir_tau: 0.0,
                dir_omega: 0.0,
            },
            s_measured: 6.3,
            s_sim: None,
            err: Some(0.01),
            signed_diff: None,
        });
        header_matches(&BifurcationRecord {
            dir: DirColumns {
                dir_kappa: 0.6,
                dir_tau: 0.8,
                dir_omega: 0.0,
            },
            s_star: 7.0,
            kind: "degenerate",
            coefficient: Real::NAN,
            s_return: Real::NAN,
            hysteresis: Real::NAN,
            resolution: "n=30".into(),
            reason: "Newton failed, at s = 7.1".into(),
        });
        header_matches(&crate::records::JointLimit {
            name: "right_j0".into(),
            lower: -3.05,
            upper: 3.05,
        });
        header_matches(&crate::records::reach::ReachRecord {
            dir: DirColumns {
                dir_kappa: 0.6,
                dir_tau: 0.8,
                dir_omega: 0.0,
            },
            s_star: 7.1,
            s_reached: 7.8,
            class: "testable",
            cause: "",
            azimuth: 0.0,
            roll_mode: "fixed",
            n_waypoints: 194,
            path_cost: 8.5,
            max_joint_step: 0.05,
            reconfigurations: 0,
            backoffs: 0,
            bifurcation: "any",
        });
    }

    /// A nested struct's names stand in its place; a field without a column name (a sequence)
    /// is an error, not a wrong header.
    #[test]
    fn field_names_flatten_nested_structs() {
        #[derive(Serialize)]
        struct Keyed {
            dir: DirColumns,
            #[serde(rename = "type")]
            kind: &'static str,
            n: Option<usize>,
        }
        let k = Keyed {
            dir: DirColumns {
                dir_kappa: 1.0,
                dir_tau: 0.0,
                dir_omega: 0.0,
            },
            kind: "x",
            n: None,
        };
        assert_eq!(
            field_names(&k).unwrap(),
            ["dir_kappa", "dir_tau", "dir_omega", "type", "n"]
        );
        assert_eq!(fields(&k).unwrap(), ["1", "0", "0", "x", ""]);
        #[derive(Serialize)]
        struct Ragged {
            q: Vec<f64>,
        }
        let e = field_names(&Ragged { q: vec![1.0] })
            .unwrap_err()
            .to_string();
        assert!(e.contains("sequence"), "{e}");
        assert!(field_names(&1.0).is_err());
    }

    /// Numbers are written as the hand-written writers did (`{}` of f64: the shortest text that
    /// reads back to the same value), and read back bit for bit.
    #[test]
    fn numbers_match_display_and_read_back() {
        let r = series();
        let text = to_csv(&[r]).unwrap();
        let by_hand = format!(
            "t,s,kappa,tau,omega,error,energy\n{},{},{},{},{},{},{}\n",
            r.t, r.s, r.kappa, r.tau, r.omega, r.error, r.energy
        );
        assert_eq!(text, by_hand);
        let f = fields(&r).unwrap();
        for (x, v) in f.iter().zip([r.t, r.s, r.kappa, r.tau, r.omega]) {
            assert_eq!(x.parse::<Real>().unwrap().to_bits(), v.to_bits());
        }
        assert_eq!(f[5], "NaN");
        assert_eq!(f[6], "inf");
    }

    /// Empty fields for values not computed; text with a comma or quote is quoted and reads
    /// back whole; the header is written for no rows.
    #[test]
    fn empty_values_quoting_and_no_rows() {
        let c = ComparisonRecord {
            dir: DirColumns {
                dir_kappa: 1.0,
                dir_tau: 0.0,
                dir_omega: 0.0,
            },
            s_measured: 6.5,
            s_sim: None,
            err: None,
            signed_diff: None,
        };
        assert_eq!(fields(&c).unwrap(), ["1", "0", "0", "6.5", "", "", ""]);
        let b = BifurcationRecord {
            dir: DirColumns {
                dir_kappa: 0.6,
                dir_tau: 0.8,
                dir_omega: 0.0,
            },
            s_star: Real::NAN,
            kind: "degenerate",
            coefficient: Real::NAN,
            s_return: 5.0,
            hysteresis: Real::NAN,
            resolution: "n=30".into(),
            reason: "Newton failed, \"no step\"".into(),
        };
        let text = to_csv(std::slice::from_ref(&b)).unwrap();
        let mut rd = csv::Reader::from_reader(text.as_bytes());
        let rec = rd.records().next().unwrap().unwrap();
        assert_eq!(&rec[3], "");
        assert_eq!(&rec[6], "5");
        assert_eq!(&rec[9], b.reason);
        assert_eq!(
            to_csv::<SpeedErrorRow>(&[]).unwrap(),
            "method,resolution,time_per_direction_s,max_rel_err,median_rel_err\n"
        );
    }
}
