//! Solomon's VRPTW files (and the Homberger–Gehring ones, which share the layout).

use super::lex::{
    MAX_NODES, ParseError, Token, expected, expected_eof, nth, number, tokens, unsigned,
};
use crate::{Instance, Metric, Node};

/// Reads a Solomon instance:
///
/// ```text
/// C101
///
/// VEHICLE
/// NUMBER     CAPACITY
///   25         200
///
/// CUSTOMER
/// CUST NO.  XCOORD.   YCOORD.    DEMAND   READY TIME  DUE DATE   SERVICE   TIME
///
///     0      40         50          0          0       1236          0
///     1      45         68         10        912        967         90
/// ```
///
/// Customer 0 is the depot (its due date closes the horizon); customers must be numbered
/// 0, 1, 2, … in order. Distances are Euclidean, not rounded; travel time equals distance.
///
/// # Errors
/// A [`ParseError`] with the line and column of the first problem.
pub fn parse_solomon(text: &str) -> Result<Instance, ParseError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty());
    let end_line = text.lines().count() + 1;
    let mut next = |what: &str| lines.next().ok_or_else(|| expected_eof(end_line, what));

    let (_, name_line) = next("the instance name")?;
    let name = name_line.trim().to_string();
    keyword_line(next("the line `VEHICLE`")?, &["VEHICLE"])?;
    keyword_line(next("the line `NUMBER CAPACITY`")?, &["NUMBER", "CAPACITY"])?;
    let (ln, line) = next("the vehicle number and capacity")?;
    let t = tokens(line, ln);
    let vehicles = unsigned(
        &nth(&t, 0, ln, line, "a vehicle number")?,
        "a vehicle number",
    )?;
    let capacity = unsigned(&nth(&t, 1, ln, line, "a capacity")?, "a capacity")?;
    keyword_line(next("the line `CUSTOMER`")?, &["CUSTOMER"])?;
    let (ln, line) = next("the column header `CUST NO. XCOORD. ...`")?;
    let t = tokens(line, ln);
    if !t[0].text.eq_ignore_ascii_case("CUST") {
        return Err(expected(&t[0], "the column header `CUST NO. XCOORD. ...`"));
    }
    let mut nodes = Vec::new();
    for (ln, line) in lines {
        let t = tokens(line, ln);
        let no = unsigned(&t[0], "a customer number")?;
        if nodes.len() >= MAX_NODES {
            return Err(ParseError::Invalid {
                line: ln,
                column: t[0].column,
                message: format!("more than the {} nodes the solvers take", MAX_NODES),
            });
        }
        if no != nodes.len() as u64 {
            return Err(ParseError::Invalid {
                line: ln,
                column: t[0].column,
                message: format!(
                    "customer {no} out of order: expected customer {}",
                    nodes.len()
                ),
            });
        }
        let field = |i: usize, what: &str| -> Result<f64, ParseError> {
            number(&nth(&t, i, ln, line, what)?, what)
        };
        let (x, y) = (field(1, "an x coordinate")?, field(2, "a y coordinate")?);
        let demand = unsigned(
            &nth(&t, 3, ln, line, "a demand")?,
            "a demand (a non-negative integer)",
        )?;
        let (ready, due, service) = (
            field(4, "a ready time")?,
            field(5, "a due date")?,
            field(6, "a service time")?,
        );
        if let Some(extra) = t.get(7) {
            return Err(expected(extra, "the end of the customer line (7 fields)"));
        }
        if due < ready {
            let tok: &Token<'_> = &t[5];
            return Err(ParseError::Invalid {
                line: ln,
                column: tok.column,
                message: format!("due date {due} is before ready time {ready}"),
            });
        }
        nodes.push(Node {
            x,
            y,
            demand,
            ready,
            due,
            service,
        });
    }
    if nodes.is_empty() {
        return Err(expected_eof(end_line, "the depot's line (customer 0)"));
    }
    let vehicles = usize::try_from(vehicles).ok();
    Ok(Instance::new(
        name,
        nodes,
        capacity,
        vehicles,
        Metric::Euclidean,
    ))
}

/// A line whose tokens start with these keywords (case-insensitive).
fn keyword_line((ln, line): (usize, &str), words: &[&str]) -> Result<(), ParseError> {
    let t = tokens(line, ln);
    for (i, w) in words.iter().enumerate() {
        let tok = nth(&t, i, ln, line, &format!("`{w}`"))?;
        if !tok.text.eq_ignore_ascii_case(w) {
            return Err(expected(&tok, &format!("`{w}`")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_file_reads_with_its_windows() {
        let text = "R0\n\nVEHICLE\nNUMBER     CAPACITY\n  2    50\n\nCUSTOMER\n\
            CUST NO.  XCOORD.   YCOORD.    DEMAND   READY TIME  DUE DATE   SERVICE   TIME\n\n\
            0 0 0 0 0 100 0\n1 3 4 10 5 20 2\n";
        let inst = parse_solomon(text).unwrap();
        assert_eq!(inst.vehicles, Some(2));
        assert_eq!(inst.capacity, 50);
        assert_eq!(inst.customers(), 1);
        assert_eq!(inst.nodes[1].ready, 5.0);
        assert_eq!(inst.nodes[1].service, 2.0);
        assert_eq!(inst.dist(0, 1), 5.0);
        assert!(inst.has_time_windows());
    }
}
