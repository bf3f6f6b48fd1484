//! Parquet copies of the result tables (feature `parquet`): one row group, zstd, typed
//! nullable columns (`uint64`, `int64`, `double`, `bool`, `string`).
//!
//! Written with parquet's own column writers, without Arrow: a table is a handful of plain
//! columns, and the Arrow layer would more than double the crate's build.

use crate::table::{Cells, Kind, Table};
use crate::value::Value;
use parquet::basic::{Compression, IntType, LogicalType, Repetition, Type as Physical, ZstdLevel};
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DataType, DoubleType, Int64Type};
use parquet::errors::ParquetError;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::{SerializedColumnWriter, SerializedFileWriter};
use parquet::schema::types::Type;
use std::sync::Arc;

/// The table as the bytes of a Parquet file.
pub fn to_parquet(table: &Table) -> Result<Vec<u8>, String> {
    write(table).map_err(|e| e.to_string())
}

/// A column's Parquet type: physical type, logical type, whether it may be null.
fn column_type(cells: &Cells) -> (Physical, Option<LogicalType>, Repetition) {
    let unsigned = Some(LogicalType::Integer(IntType {
        bit_width: 64,
        is_signed: false,
    }));
    let signed = Some(LogicalType::Integer(IntType {
        bit_width: 64,
        is_signed: true,
    }));
    match cells {
        Cells::UInt(_) => (Physical::INT64, unsigned, Repetition::REQUIRED),
        Cells::Values(kind, _) => match kind {
            Kind::UInt | Kind::Int => (Physical::INT64, signed, Repetition::OPTIONAL),
            Kind::Float => (Physical::DOUBLE, None, Repetition::OPTIONAL),
            Kind::Bool => (Physical::BOOLEAN, None, Repetition::OPTIONAL),
            Kind::Text => (
                Physical::BYTE_ARRAY,
                Some(LogicalType::String),
                Repetition::OPTIONAL,
            ),
        },
    }
}

fn write(table: &Table) -> Result<Vec<u8>, ParquetError> {
    let mut fields = Vec::with_capacity(table.columns.len());
    for c in &table.columns {
        let (physical, logical, repetition) = column_type(&c.cells);
        let field = Type::primitive_type_builder(&c.name, physical)
            .with_repetition(repetition)
            .with_logical_type(logical)
            .build()?;
        fields.push(Arc::new(field));
    }
    let schema = Type::group_type_builder("schema")
        .with_fields(fields)
        .build()?;
    let props = WriterProperties::builder()
        .set_compression(Compression::ZSTD(ZstdLevel::default()))
        .build();
    let mut out = Vec::new();
    let mut file = SerializedFileWriter::new(&mut out, Arc::new(schema), Arc::new(props))?;
    let mut group = file.next_row_group()?;
    for c in &table.columns {
        let Some(mut column) = group.next_column()? else {
            return Err(ParquetError::General(format!(
                "no writer for column {}",
                c.name
            )));
        };
        match &c.cells {
            // Parquet keeps unsigned 64-bit integers in INT64's bits.
            Cells::UInt(v) => {
                let bits: Vec<i64> = v.iter().map(|&x| x as i64).collect();
                column.typed::<Int64Type>().write_batch(&bits, None, None)?;
            }
            Cells::Values(Kind::UInt | Kind::Int, v) => {
                optional::<Int64Type>(&mut column, v, |x| match x {
                    Value::Int(i) => Some(*i),
                    _ => None,
                })?
            }
            Cells::Values(Kind::Float, v) => optional::<DoubleType>(&mut column, v, Value::as_f64)?,
            Cells::Values(Kind::Bool, v) => optional::<BoolType>(&mut column, v, |x| match x {
                Value::Bool(b) => Some(*b),
                _ => None,
            })?,
            Cells::Values(Kind::Text, v) => optional::<ByteArrayType>(&mut column, v, |x| {
                Some(ByteArray::from(x.to_string().into_bytes()))
            })?,
        }
        column.close()?;
    }
    group.close()?;
    file.close()?;
    Ok(out)
}

/// Writes a nullable column: the present values and a definition level per row (1 present,
/// 0 null).
fn optional<T: DataType>(
    column: &mut SerializedColumnWriter<'_>,
    cells: &[Option<Value>],
    value: impl Fn(&Value) -> Option<T::T>,
) -> Result<(), ParquetError> {
    let mut values = Vec::with_capacity(cells.len());
    let mut levels = Vec::with_capacity(cells.len());
    for cell in cells {
        match cell.as_ref().and_then(&value) {
            Some(v) => {
                values.push(v);
                levels.push(1);
            }
            None => levels.push(0),
        }
    }
    column
        .typed::<T>()
        .write_batch(&values, Some(&levels), None)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::Column;
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;

    #[test]
    fn writes_a_parquet_file_that_reads_back() {
        let t = Table {
            columns: vec![
                Column {
                    name: "run".into(),
                    cells: Cells::UInt(vec![0, u64::MAX]),
                },
                Column {
                    name: "m".into(),
                    cells: Cells::Values(Kind::Float, vec![Some(Value::Float(0.5)), None]),
                },
                Column {
                    name: "n".into(),
                    cells: Cells::Values(Kind::Int, vec![None, Some(Value::Int(-3))]),
                },
                Column {
                    name: "ok".into(),
                    cells: Cells::Values(Kind::Bool, vec![Some(Value::Bool(true)), None]),
                },
                Column {
                    name: "s".into(),
                    cells: Cells::Values(Kind::Text, vec![None, Some(Value::Text("x y".into()))]),
                },
            ],
            rows: 2,
        };
        let bytes = to_parquet(&t).unwrap();
        assert_eq!(&bytes[..4], b"PAR1");
        assert_eq!(&bytes[bytes.len() - 4..], b"PAR1");
        let reader = SerializedFileReader::new(bytes::Bytes::from(bytes)).unwrap();
        let rows: Vec<Vec<Field>> = reader
            .get_row_iter(None)
            .unwrap()
            .map(|r| {
                r.unwrap()
                    .into_columns()
                    .into_iter()
                    .map(|(_, f)| f)
                    .collect()
            })
            .collect();
        assert_eq!(
            rows,
            vec![
                vec![
                    Field::ULong(0),
                    Field::Double(0.5),
                    Field::Null,
                    Field::Bool(true),
                    Field::Null
                ],
                vec![
                    Field::ULong(u64::MAX),
                    Field::Null,
                    Field::Long(-3),
                    Field::Null,
                    Field::Str("x y".into())
                ],
            ]
        );
    }
}
