//! Bad files are typed errors naming the line, the column and what was expected.

use vitro_routing::parse::{parse_cvrplib, parse_solomon};
use vitro_routing::{ParseError, parse};

const GOOD_VRP: &str = "NAME : t-n3-k1\nTYPE : CVRP\nDIMENSION : 3\nEDGE_WEIGHT_TYPE : EUC_2D\n\
CAPACITY : 10\nNODE_COORD_SECTION\n1 0 0\n2 3 4\n3 6 8\nDEMAND_SECTION\n1 0\n2 4\n3 5\n\
DEPOT_SECTION\n1\n-1\nEOF\n";

const GOOD_SOLOMON: &str = "R0\n\nVEHICLE\nNUMBER     CAPACITY\n  2    50\n\nCUSTOMER\n\
CUST NO.  XCOORD.   YCOORD.    DEMAND   READY TIME  DUE DATE   SERVICE   TIME\n\n\
    0      0      0      0      0    100      0\n\
    1      3      4     10      5     20      2\n";

fn place(e: &ParseError) -> (usize, usize) {
    match e {
        ParseError::Expected { line, column, .. }
        | ParseError::Unsupported { line, column, .. }
        | ParseError::Invalid { line, column, .. } => (*line, *column),
        other => panic!("unknown error {other:?}"),
    }
}

#[test]
fn the_good_files_read() {
    let v = parse(GOOD_VRP).unwrap();
    assert_eq!((v.customers(), v.capacity, v.vehicles), (2, 10, Some(1)));
    let s = parse(GOOD_SOLOMON).unwrap();
    assert_eq!((s.customers(), s.capacity, s.vehicles), (1, 50, Some(2)));
}

#[test]
fn a_bad_coordinate_names_its_line_and_column() {
    let text = GOOD_VRP.replace("2 3 4\n", "2 3 x4\n");
    let e = parse_cvrplib(&text).unwrap_err();
    assert_eq!(place(&e), (8, 5));
    let msg = e.to_string();
    assert!(
        msg.contains("line 8, column 5")
            && msg.contains("a y coordinate")
            && msg.contains("\"x4\""),
        "{msg}"
    );
}

#[test]
fn a_missing_field_is_found_at_the_end_of_its_line() {
    let text = GOOD_VRP.replace("3 6 8\n", "3 6\n");
    let e = parse_cvrplib(&text).unwrap_err();
    assert_eq!(place(&e), (9, 4));
    assert!(e.to_string().contains("end of line"), "{e}");
}

#[test]
fn a_header_value_is_located_after_its_colon() {
    let e = parse_cvrplib(&GOOD_VRP.replace("CAPACITY : 10", "CAPACITY : ten")).unwrap_err();
    assert_eq!(place(&e), (5, 12));
    assert!(e.to_string().contains("a capacity"), "{e}");
}

#[test]
fn unsupported_distances_are_refused() {
    let e = parse_cvrplib(&GOOD_VRP.replace("EUC_2D", "GEO")).unwrap_err();
    assert!(
        matches!(
            e,
            ParseError::Unsupported {
                line: 4,
                column: 20,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn node_ids_are_checked() {
    let e = parse_cvrplib(&GOOD_VRP.replace("3 6 8\n", "2 6 8\n")).unwrap_err();
    assert!(
        matches!(
            e,
            ParseError::Invalid {
                line: 9,
                column: 1,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("given twice"), "{e}");
    let e = parse_cvrplib(&GOOD_VRP.replace("3 6 8\n", "4 6 8\n")).unwrap_err();
    assert!(e.to_string().contains("not in 1..=3"), "{e}");
}

#[test]
fn a_truncated_file_says_what_it_lacked() {
    let cut = &GOOD_VRP[..GOOD_VRP.find("DEMAND_SECTION").unwrap()];
    let e = parse_cvrplib(cut).unwrap_err();
    assert!(
        matches!(&e, ParseError::Expected { found, .. } if found == "end of file"),
        "{e:?}"
    );
    assert!(e.to_string().contains("DEMAND_SECTION"), "{e}");
    let cut = &GOOD_VRP[..GOOD_VRP.find("3 6 8").unwrap()];
    let e = parse_cvrplib(cut).unwrap_err();
    assert_eq!(place(&e), (9, 1));
    assert!(e.to_string().contains("node line"), "{e}");
}

#[test]
fn a_section_before_dimension_is_refused() {
    let e = parse_cvrplib("NAME : x\nNODE_COORD_SECTION\n1 0 0\n").unwrap_err();
    assert_eq!(place(&e), (2, 1));
    assert!(e.to_string().contains("DIMENSION"), "{e}");
}

#[test]
fn solomon_errors_name_line_and_column() {
    let e = parse_solomon(&GOOD_SOLOMON.replace("  2    50", "  2    fifty")).unwrap_err();
    assert_eq!(place(&e), (5, 8));
    assert!(e.to_string().contains("a capacity"), "{e}");

    let e = parse_solomon(&GOOD_SOLOMON.replace("\n1      3", "\n2      3")).unwrap_err();
    assert!(
        matches!(
            e,
            ParseError::Invalid {
                line: 11,
                column: 1,
                ..
            }
        ),
        "{e:?}"
    );

    let e = parse_solomon(&GOOD_SOLOMON.replace("     20      2\n", "     20\n")).unwrap_err();
    assert!(e.to_string().contains("a service time"), "{e}");
    // "1      3      4     10      5     20" is 36 characters: the service time was due at 37.
    assert_eq!(place(&e), (11, 37));

    let e = parse_solomon(&GOOD_SOLOMON.replace("VEHICLE", "VEHICLES")).unwrap_err();
    assert_eq!(place(&e), (3, 1));

    let e = parse_solomon("R0\n\nVEHICLE\n").unwrap_err();
    assert!(
        matches!(&e, ParseError::Expected { line: 4, found, .. } if found == "end of file"),
        "{e:?}"
    );

    let e = parse_solomon(&GOOD_SOLOMON.replace("      5     20", "     30     20")).unwrap_err();
    assert!(e.to_string().contains("before ready time"), "{e}");
}

#[test]
fn garbage_never_panics() {
    let inputs = [
        "",
        "\n\n",
        ":",
        "NAME",
        "DEPOT_SECTION",
        "x\ny\nz",
        "\u{feff}NAME : \u{e9}",
        "0 0 0",
    ];
    for text in inputs {
        let _ = parse(text);
    }
    // Every prefix and every one-byte corruption of the good files.
    for good in [GOOD_VRP, GOOD_SOLOMON] {
        for cut in 0..good.len() {
            let _ = parse(&good[..cut]);
            let mut bytes = good.as_bytes().to_vec();
            bytes[cut] = b'#';
            let _ = parse(&String::from_utf8_lossy(&bytes));
        }
    }
}

#[test]
fn a_dimension_beyond_the_solvers_is_refused_at_its_value() {
    let text = GOOD_VRP.replace("DIMENSION : 3", "DIMENSION : 10001");
    let e = parse(&text).unwrap_err();
    assert_eq!(place(&e), (3, 13), "{e}");
    assert!(e.to_string().contains("10000 nodes"), "{e}");
    // The fuzz target's find: a 17-digit DIMENSION once asked for that many slots.
    let found = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fuzz_regressions/huge_dimension.vrp"
    ))
    .unwrap();
    let e = parse(&String::from_utf8_lossy(&found)).unwrap_err();
    assert!(e.to_string().contains("DIMENSION"), "{e}");
}

#[test]
fn a_solomon_file_beyond_the_solvers_is_refused_at_the_first_extra_customer() {
    // The good file up to its depot (customer 0), then customers 1 to 10,000.
    let depot_end = GOOD_SOLOMON.find("\n1 ").expect("customer 1's line") + 1;
    let mut text = GOOD_SOLOMON[..depot_end].to_string();
    for i in 1..=10_000 {
        text.push_str(&format!(
            "    {i}      3      4     1      5     20      2\n"
        ));
    }
    let e = parse_solomon(&text).unwrap_err();
    assert_eq!(place(&e).0, 10 + 10_000, "{e}");
    assert!(e.to_string().contains("10000 nodes"), "{e}");
}
