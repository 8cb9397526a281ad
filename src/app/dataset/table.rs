//! A dataset's tables: the columns of a table (its schema), a case's rows of it as columns
//! (a [`Block`]), and a Parquet file written row group by row group ([`ParquetTable`]).
//!
//! A measurement table is the CSV that `mtwin run` writes for a test, read back: every kind's
//! table is in datasets without the dataset code knowing it. Its `# key = value` preamble
//! lines (the test's set-up: plane, radius, feed, …) become columns as well (prefixed `meta_`
//! if a data column or a partition key has the same name: `machine` is both a preamble line
//! and the `machine=` key, and pandas refuses a file column that repeats a partition key), so
//! each row stands alone; a line holding a vector (`# centre_mm = 380 205 300`) becomes one
//! number column per component (`centre_x_mm`, `centre_y_mm`, `centre_z_mm`). A column is a number
//! (Parquet DOUBLE) if every value of the schema's first case reads as one, else text (UTF-8);
//! empty cells are nulls. `case_id` comes first in every table.

use super::priors::unit_suffix;
use arrow_schema::{DataType, Field};
use parquet::arrow::{ARROW_SCHEMA_META_KEY, encode_arrow_schema};
use parquet::basic::{Compression, LogicalType, Repetition, Type as PhysicalType};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::{ColumnPath, Type};
use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;
use std::sync::Arc;

/// Values buffered per file before a row group is written (about 16 MB of doubles, 32 MB as
/// buffered): memory stays bounded whatever the number of cases.
const ROW_GROUP_VALUES: usize = 2_000_000;

/// The Hive partition keys of a table's folder (`machine=…/split=…/shard=…`).
pub const PARTITION_KEYS: [&str; 3] = ["machine", "split", "shard"];

/// What a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColumnKind {
    /// 64-bit integers, never null (`case_id`, `case_seed`).
    Integer,
    /// 64-bit floats, nullable.
    Number,
    /// UTF-8 text, nullable.
    Text,
}

/// The columns of one table, in order (the first is `case_id`).
#[derive(Clone, Debug, PartialEq)]
pub struct TableSchema {
    /// Its name (`cases`, `volumetric`, `ballbar_xy`, …): the table's folder.
    pub name: String,
    /// Name and kind of every column.
    pub columns: Vec<(String, ColumnKind)>,
    /// The CSV preamble's `key = value` lines, in order: how many columns each makes (1, or
    /// the number of components of a vector). Their columns follow `case_id`.
    pub preamble: Vec<usize>,
}

/// The components of a preamble value if it is a vector (two or more numbers separated by
/// spaces, as in `380 205 300`), else `None`.
fn vector(value: &str) -> Option<Vec<f64>> {
    let parts: Vec<f64> = (value.split_whitespace())
        .map(|part| part.parse::<f64>().ok())
        .collect::<Option<_>>()?;
    (parts.len() >= 2).then_some(parts)
}

/// The column names of a vector's components: `centre_mm` → `centre_x_mm`, `centre_y_mm`,
/// `centre_z_mm` (x, y, z for three components, else 0, 1, …), the unit suffix kept last.
fn component_names(key: &str, count: usize) -> Vec<String> {
    let suffix = unit_suffix(key).unwrap_or("");
    let stem = &key[..key.len() - suffix.len()];
    (0..count)
        .map(|i| {
            let component = match (count, i) {
                (3, 0) => "x".to_string(),
                (3, 1) => "y".to_string(),
                (3, 2) => "z".to_string(),
                _ => i.to_string(),
            };
            format!("{stem}_{component}{suffix}")
        })
        .collect()
}

/// A CSV table read into lines: the preamble's pairs, the header and the rows.
struct Csv<'a> {
    preamble: Vec<(&'a str, &'a str)>,
    header: Vec<&'a str>,
    rows: Vec<Vec<&'a str>>,
}

fn read_csv(text: &str) -> Result<Csv<'_>, String> {
    let mut preamble = Vec::new();
    let mut lines = text.lines();
    let header = loop {
        let line = lines.next().ok_or("no header line")?;
        match line.strip_prefix('#') {
            Some(comment) => {
                if let Some((key, value)) = comment.split_once('=') {
                    preamble.push((key.trim(), value.trim()));
                }
            }
            None => break line.split(',').map(str::trim).collect::<Vec<_>>(),
        }
    };
    let mut rows = Vec::new();
    for (index, line) in lines.enumerate() {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let row: Vec<&str> = line.split(',').map(str::trim).collect();
        if row.len() != header.len() {
            return Err(format!(
                "row {} has {} values for {} columns",
                index + 1,
                row.len(),
                header.len()
            ));
        }
        rows.push(row);
    }
    Ok(Csv {
        preamble,
        header,
        rows,
    })
}

impl TableSchema {
    /// The `cases` table: `case_id`, `case_seed` and one number per prior.
    pub fn cases(parameters: impl IntoIterator<Item = String>) -> TableSchema {
        let mut columns = vec![
            ("case_id".to_string(), ColumnKind::Integer),
            ("case_seed".to_string(), ColumnKind::Integer),
        ];
        columns.extend(parameters.into_iter().map(|p| (p, ColumnKind::Number)));
        TableSchema {
            name: "cases".into(),
            columns,
            preamble: Vec::new(),
        }
    }

    /// The schema of the table `name` whose CSV (from the schema's first case) is `text`.
    pub fn of_csv(name: &str, text: &str) -> Result<TableSchema, String> {
        let csv = read_csv(text)?;
        fn number<'v>(mut values: impl Iterator<Item = &'v str>) -> ColumnKind {
            if values.all(|v| v.is_empty() || v.parse::<f64>().is_ok()) {
                ColumnKind::Number
            } else {
                ColumnKind::Text
            }
        }
        let mut columns = vec![("case_id".to_string(), ColumnKind::Integer)];
        let mut preamble = Vec::new();
        let column_name = |name: String| {
            if csv.header.contains(&name.as_str()) || PARTITION_KEYS.contains(&name.as_str()) {
                format!("meta_{name}")
            } else {
                name
            }
        };
        for (key, value) in &csv.preamble {
            match vector(value) {
                Some(parts) => {
                    for name in component_names(key, parts.len()) {
                        columns.push((column_name(name), ColumnKind::Number));
                    }
                    preamble.push(parts.len());
                }
                None => {
                    columns.push((
                        column_name(key.to_string()),
                        number(std::iter::once(*value)),
                    ));
                    preamble.push(1);
                }
            }
        }
        for (index, column) in csv.header.iter().enumerate() {
            let kind = number(csv.rows.iter().map(|row| row[index]));
            columns.push((column.to_string(), kind));
        }
        let schema = TableSchema {
            name: name.to_string(),
            columns,
            preamble,
        };
        let mut seen = std::collections::BTreeSet::new();
        if let Some((name, _)) = schema
            .columns
            .iter()
            .find(|(n, _)| !seen.insert(n.as_str()))
        {
            return Err(format!("the column {name} appears twice"));
        }
        Ok(schema)
    }

    /// The Arrow schema of the same columns, each column's unit (from `units`, one per
    /// column; none where empty) in its field metadata `unit`, and the file's `metadata` as
    /// its own: what pyarrow, polars and the parquet crate's Arrow reader find in the file's
    /// `ARROW:schema` (pyarrow's `schema.metadata` is this one's, not the file's).
    fn arrow(&self, units: &[String], metadata: &[(String, String)]) -> arrow_schema::Schema {
        let fields: Vec<Field> = (self.columns.iter())
            .zip(
                units
                    .iter()
                    .map(String::as_str)
                    .chain(std::iter::repeat("")),
            )
            .map(|((name, kind), unit)| {
                let field = match kind {
                    ColumnKind::Integer => Field::new(name, DataType::Int64, false),
                    ColumnKind::Number => Field::new(name, DataType::Float64, true),
                    ColumnKind::Text => Field::new(name, DataType::Utf8, true),
                };
                if unit.is_empty() {
                    field
                } else {
                    field.with_metadata(HashMap::from([("unit".to_string(), unit.to_string())]))
                }
            })
            .collect();
        arrow_schema::Schema::new_with_metadata(fields, metadata.iter().cloned().collect())
    }

    /// The Parquet schema.
    fn parquet(&self) -> Type {
        let fields = self
            .columns
            .iter()
            .map(|(name, kind)| {
                let (physical, repetition, logical) = match kind {
                    ColumnKind::Integer => (PhysicalType::INT64, Repetition::REQUIRED, None),
                    ColumnKind::Number => (PhysicalType::DOUBLE, Repetition::OPTIONAL, None),
                    ColumnKind::Text => (
                        PhysicalType::BYTE_ARRAY,
                        Repetition::OPTIONAL,
                        Some(LogicalType::String),
                    ),
                };
                Arc::new(
                    Type::primitive_type_builder(name, physical)
                        .with_repetition(repetition)
                        .with_logical_type(logical)
                        .build()
                        .expect("a valid primitive column"),
                )
            })
            .collect();
        Type::group_type_builder("schema")
            .with_fields(fields)
            .build()
            .expect("a valid schema")
    }
}

/// One column's values in a [`Block`].
#[derive(Clone, Debug, PartialEq)]
enum Values {
    Integer(Vec<i64>),
    Number(Vec<Option<f64>>),
    /// Text, each distinct value of a block stored once (a `ByteArray` clone shares it).
    Text(Vec<Option<ByteArray>>),
}

/// Rows of one table as columns, in the table's schema.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    rows: usize,
    columns: Vec<Values>,
}

impl Block {
    /// The `cases` row of one case.
    pub fn case_row(id: u64, seed: u64, values: &[f64]) -> Block {
        let mut columns = vec![
            Values::Integer(vec![id as i64]),
            Values::Integer(vec![seed as i64]),
        ];
        columns.extend(values.iter().map(|v| Values::Number(vec![Some(*v)])));
        Block { rows: 1, columns }
    }

    /// Case `id`'s rows of a table of `schema`, from its CSV `text`.
    pub fn from_csv(schema: &TableSchema, id: u64, text: &str) -> Result<Block, String> {
        let csv = read_csv(text)?;
        let width: usize = schema.preamble.iter().sum();
        let names: Vec<&str> = schema.columns[1 + width..]
            .iter()
            .map(|(n, _)| n.as_str())
            .collect();
        if csv.header != names || csv.preamble.len() != schema.preamble.len() {
            return Err(format!(
                "its columns ({}; {} preamble lines) are not the dataset's ({}; {}), which come from the priors' centres",
                csv.header.join(","),
                csv.preamble.len(),
                names.join(","),
                schema.preamble.len()
            ));
        }
        // Each preamble column's cell: the line's value, or one component of its vector.
        let mut preamble_cells: Vec<&str> = Vec::with_capacity(width);
        for ((key, value), &parts) in csv.preamble.iter().zip(&schema.preamble) {
            if parts == 1 {
                preamble_cells.push(*value);
            } else {
                let components: Vec<&str> = value.split_whitespace().collect();
                if components.len() != parts {
                    return Err(format!(
                        "the preamble's {key} = {value} has {} components, the dataset's {parts}",
                        components.len()
                    ));
                }
                preamble_cells.extend(components);
            }
        }
        let rows = csv.rows.len();
        let mut columns = vec![Values::Integer(vec![id as i64; rows])];
        let cells = |index: usize| -> Box<dyn Iterator<Item = &str> + '_> {
            if index < width {
                Box::new(std::iter::repeat_n(preamble_cells[index], rows))
            } else {
                let i = index - width;
                Box::new(csv.rows.iter().map(move |row| row[i]))
            }
        };
        for (index, (name, kind)) in schema.columns[1..].iter().enumerate() {
            let values = match kind {
                ColumnKind::Number => Values::Number(
                    cells(index)
                        .map(|cell| {
                            if cell.is_empty() {
                                Ok(None)
                            } else {
                                cell.parse::<f64>()
                                    .map(Some)
                                    .map_err(|_| format!("{name}: `{cell}` is not a number"))
                            }
                        })
                        .collect::<Result<_, _>>()?,
                ),
                ColumnKind::Text => {
                    // Text columns hold few distinct values (a direction, the plane, a test's
                    // name): each is made once per block.
                    let mut seen: Vec<(String, ByteArray)> = Vec::new();
                    let mut text = |cell: &str| {
                        if let Some((_, bytes)) = seen.iter().find(|(s, _)| *s == cell) {
                            return bytes.clone();
                        }
                        let bytes = ByteArray::from(cell);
                        if seen.len() < 64 {
                            seen.push((cell.to_string(), bytes.clone()));
                        }
                        bytes
                    };
                    Values::Text(
                        cells(index)
                            .map(|cell| (!cell.is_empty()).then(|| text(cell)))
                            .collect(),
                    )
                }
                ColumnKind::Integer => unreachable!("only case_id is an integer column"),
            };
            columns.push(values);
        }
        Ok(Block { rows, columns })
    }

    /// Its number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }
}

/// A Parquet file being written: blocks are buffered and written as a row group once
/// [`ROW_GROUP_VALUES`] values are waiting.
pub struct ParquetTable {
    writer: SerializedFileWriter<BufWriter<File>>,
    buffer: Vec<Values>,
    buffered_rows: usize,
    width: usize,
    rows: u64,
}

/// Why a Parquet file could not be written.
pub type ParquetError = parquet::errors::ParquetError;

impl ParquetTable {
    /// Creates `path` for a table of `schema`, with `metadata` as the file's key-value
    /// metadata and `units` (one per column, empty for none) as each column's field metadata
    /// `unit`.
    pub fn create(
        path: &Path,
        schema: &TableSchema,
        metadata: Vec<(String, String)>,
        units: &[String],
    ) -> Result<ParquetTable, ParquetError> {
        let file = File::create(path)?;
        // Dictionaries for text and the integer ids (few distinct values), not for measured
        // doubles: hashing every reading costs more than it saves.
        let mut properties = WriterProperties::builder().set_dictionary_enabled(false);
        for (name, kind) in &schema.columns {
            if *kind != ColumnKind::Number {
                properties =
                    properties.set_column_dictionary_enabled(ColumnPath::from(name.as_str()), true);
            }
        }
        let properties = properties
            .set_compression(Compression::SNAPPY)
            .set_created_by(format!("mtwin {}", env!("CARGO_PKG_VERSION")))
            .set_key_value_metadata(Some(
                (metadata.iter())
                    .map(|(key, value)| KeyValue::new(key.clone(), value.clone()))
                    .chain([KeyValue::new(
                        ARROW_SCHEMA_META_KEY.to_string(),
                        encode_arrow_schema(&schema.arrow(units, &metadata)),
                    )])
                    .collect(),
            ))
            .build();
        let writer = SerializedFileWriter::new(
            BufWriter::new(file),
            Arc::new(schema.parquet()),
            Arc::new(properties),
        )?;
        let buffer = schema
            .columns
            .iter()
            .map(|(_, kind)| match kind {
                ColumnKind::Integer => Values::Integer(Vec::new()),
                ColumnKind::Number => Values::Number(Vec::new()),
                ColumnKind::Text => Values::Text(Vec::new()),
            })
            .collect();
        Ok(ParquetTable {
            writer,
            buffer,
            buffered_rows: 0,
            width: schema.columns.len(),
            rows: 0,
        })
    }

    /// Appends `block`'s rows.
    pub fn push(&mut self, block: Block) -> Result<(), ParquetError> {
        for (buffer, values) in self.buffer.iter_mut().zip(block.columns) {
            match (buffer, values) {
                (Values::Integer(b), Values::Integer(v)) => b.extend(v),
                (Values::Number(b), Values::Number(v)) => b.extend(v),
                (Values::Text(b), Values::Text(v)) => b.extend(v),
                _ => unreachable!("blocks are made in the table's schema"),
            }
        }
        self.buffered_rows += block.rows;
        if self.buffered_rows * self.width >= ROW_GROUP_VALUES {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes the buffered rows as one row group.
    fn flush(&mut self) -> Result<(), ParquetError> {
        if self.buffered_rows == 0 {
            return Ok(());
        }
        let mut group = self.writer.next_row_group()?;
        for values in &mut self.buffer {
            let mut column = group.next_column()?.expect("one column per buffer");
            match values {
                Values::Integer(v) => {
                    column.typed::<Int64Type>().write_batch(v, None, None)?;
                    v.clear();
                }
                Values::Number(v) => {
                    let levels: Vec<i16> = v.iter().map(|x| i16::from(x.is_some())).collect();
                    let present: Vec<f64> = v.iter().flatten().copied().collect();
                    column
                        .typed::<DoubleType>()
                        .write_batch(&present, Some(&levels), None)?;
                    v.clear();
                }
                Values::Text(v) => {
                    let levels: Vec<i16> = v.iter().map(|x| i16::from(x.is_some())).collect();
                    let present: Vec<ByteArray> = v.iter().flatten().cloned().collect();
                    column
                        .typed::<ByteArrayType>()
                        .write_batch(&present, Some(&levels), None)?;
                    v.clear();
                }
            }
            column.close()?;
        }
        group.close()?;
        self.rows += self.buffered_rows as u64;
        self.buffered_rows = 0;
        Ok(())
    }

    /// Writes what is buffered and closes the file; returns its number of rows.
    pub fn finish(mut self) -> Result<u64, ParquetError> {
        self.flush()?;
        self.writer.close()?;
        Ok(self.rows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BALLBAR: &str = "# mtwin ballbar table\n# plane = XY\n# machine = vmc3\n# radius_mm = 150\ndirection,angle_deg,deviation_um\nccw,0.5,-1.25\ncw,,2\n";

    #[test]
    fn preamble_and_cells_become_typed_columns() {
        let schema = TableSchema::of_csv("ballbar_xy", BALLBAR).unwrap();
        let kinds: Vec<(&str, ColumnKind)> = schema
            .columns
            .iter()
            .map(|(n, k)| (n.as_str(), *k))
            .collect();
        assert_eq!(
            kinds,
            [
                ("case_id", ColumnKind::Integer),
                ("plane", ColumnKind::Text),
                ("meta_machine", ColumnKind::Text),
                ("radius_mm", ColumnKind::Number),
                ("direction", ColumnKind::Text),
                ("angle_deg", ColumnKind::Number),
                ("deviation_um", ColumnKind::Number),
            ]
        );
        let block = Block::from_csv(&schema, 7, BALLBAR).unwrap();
        assert_eq!(block.rows(), 2);
        assert_eq!(block.columns[0], Values::Integer(vec![7, 7]));
        assert_eq!(
            block.columns[3],
            Values::Number(vec![Some(150.0), Some(150.0)])
        );
        assert_eq!(block.columns[5], Values::Number(vec![Some(0.5), None]));
        assert_eq!(
            block.columns[4],
            Values::Text(vec![Some("ccw".into()), Some("cw".into())])
        );
    }

    #[test]
    fn a_case_with_other_columns_or_text_in_a_number_column_is_refused() {
        let schema = TableSchema::of_csv("ballbar_xy", BALLBAR).unwrap();
        let other = BALLBAR.replace("deviation_um", "radius_um");
        assert!(
            Block::from_csv(&schema, 0, &other)
                .unwrap_err()
                .contains("not the dataset's")
        );
        let text = BALLBAR.replace("-1.25", "n/a");
        assert!(
            Block::from_csv(&schema, 0, &text)
                .unwrap_err()
                .contains("`n/a` is not a number")
        );
        assert!(Block::from_csv(&schema, 0, "a,b\n1,2,3\n").is_err());
    }

    #[test]
    fn a_vector_in_the_preamble_becomes_one_number_column_per_component() {
        let text =
            "# plane = XY\n# centre_mm = 380 205.5 -300\nangle_deg,deviation_um\n0,1\n90,2\n";
        let schema = TableSchema::of_csv("ballbar_xy", text).unwrap();
        let names: Vec<&str> = schema.columns.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "case_id",
                "plane",
                "centre_x_mm",
                "centre_y_mm",
                "centre_z_mm",
                "angle_deg",
                "deviation_um"
            ]
        );
        assert_eq!(schema.preamble, [1, 3]);
        assert!(
            schema.columns[2..5]
                .iter()
                .all(|(_, k)| *k == ColumnKind::Number)
        );
        let block = Block::from_csv(&schema, 3, text).unwrap();
        let expected = [380.0, 205.5, -300.0];
        for (column, value) in block.columns[2..5].iter().zip(expected) {
            assert_eq!(*column, Values::Number(vec![Some(value), Some(value)]));
        }
        // A case whose vector has another number of components does not fit the schema.
        let short = text.replace("380 205.5 -300", "380 205.5");
        assert!(
            Block::from_csv(&schema, 3, &short)
                .unwrap_err()
                .contains("components")
        );
    }
}
