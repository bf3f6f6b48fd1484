//! Parquet copies of the result tables (feature `parquet`): one row group, zstd, typed
//! nullable columns (`uint64`, `int64`, `double`, `bool`, `string`).

use crate::table::{Cells, Kind, Table};
use crate::value::Value;
use arrow_array::{
    ArrayRef, BooleanArray, Float64Array, Int64Array, RecordBatch, StringArray, UInt64Array,
};
use arrow_schema::{DataType, Field, Schema};
use parquet::arrow::ArrowWriter;
use parquet::basic::{Compression, ZstdLevel};
use parquet::file::properties::WriterProperties;
use std::sync::Arc;

/// The table as the bytes of a Parquet file.
pub fn to_parquet(table: &Table) -> Result<Vec<u8>, String> {
    let mut fields = Vec::with_capacity(table.columns.len());
    let mut arrays: Vec<ArrayRef> = Vec::with_capacity(table.columns.len());
    for c in &table.columns {
        let (data_type, nullable, array): (DataType, bool, ArrayRef) = match &c.cells {
            Cells::UInt(v) => (
                DataType::UInt64,
                false,
                Arc::new(UInt64Array::from(v.clone())),
            ),
            Cells::Values(kind, v) => match kind {
                Kind::UInt | Kind::Int => (
                    DataType::Int64,
                    true,
                    Arc::new(Int64Array::from_iter(v.iter().map(|x| match x {
                        Some(Value::Int(i)) => Some(*i),
                        _ => None,
                    }))),
                ),
                Kind::Float => (
                    DataType::Float64,
                    true,
                    Arc::new(Float64Array::from_iter(
                        v.iter().map(|x| x.as_ref().and_then(Value::as_f64)),
                    )),
                ),
                Kind::Bool => (
                    DataType::Boolean,
                    true,
                    Arc::new(BooleanArray::from_iter(v.iter().map(|x| match x {
                        Some(Value::Bool(b)) => Some(*b),
                        _ => None,
                    }))),
                ),
                Kind::Text => (
                    DataType::Utf8,
                    true,
                    Arc::new(StringArray::from_iter(
                        v.iter().map(|x| x.as_ref().map(Value::to_string)),
                    )),
                ),
            },
        };
        fields.push(Field::new(&c.name, data_type, nullable));
        arrays.push(array);
    }
    let schema = Arc::new(Schema::new(fields));
    let batch = RecordBatch::try_new(schema.clone(), arrays).map_err(|e| e.to_string())?;
    let props = WriterProperties::builder()
        .set_compression(Compression::ZSTD(ZstdLevel::default()))
        .build();
    let mut out = Vec::new();
    let mut w = ArrowWriter::try_new(&mut out, schema, Some(props)).map_err(|e| e.to_string())?;
    w.write(&batch).map_err(|e| e.to_string())?;
    w.close().map_err(|e| e.to_string())?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::Column;

    #[test]
    fn writes_a_parquet_file() {
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
            ],
            rows: 2,
        };
        let bytes = to_parquet(&t).unwrap();
        assert_eq!(&bytes[..4], b"PAR1");
        assert_eq!(&bytes[bytes.len() - 4..], b"PAR1");
    }
}
