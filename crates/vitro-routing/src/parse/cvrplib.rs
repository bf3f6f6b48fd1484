//! CVRPLIB's TSPLIB-style `.vrp` files (`EDGE_WEIGHT_TYPE : EUC_2D`).

use super::lex::{
    MAX_NODES, ParseError, Token, expected, expected_at_end, expected_eof, nth, number, tokens,
    unsigned,
};
use crate::{Instance, Metric, Node};

/// Reads a CVRPLIB instance: the headers `NAME`, `COMMENT`, `TYPE : CVRP`, `DIMENSION`,
/// `CAPACITY`, `EDGE_WEIGHT_TYPE : EUC_2D` (optionally `VEHICLES`), then `NODE_COORD_SECTION`,
/// `DEMAND_SECTION`, `DEPOT_SECTION` (one depot, ended by `-1`) and `EOF`.
///
/// The depot becomes node 0 and the others keep their order, so customer `k` is the file's node
/// `k + 1` when the depot is node 1 (CVRPLIB's solution numbering). Distances are TSPLIB's
/// rounded Euclidean ones. The fleet size is `VEHICLES`, else the `k` of a name like
/// `A-n32-k5`; a best-known cost is read from a comment such as `Optimal value: 784`.
///
/// # Errors
/// A [`ParseError`] with the line and column of the first problem.
pub fn parse_cvrplib(text: &str) -> Result<Instance, ParseError> {
    let lines: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty())
        .collect();
    let end_line = text.lines().count() + 1;
    let mut h = Headers::default();
    let mut coords: Option<Vec<Option<(f64, f64)>>> = None;
    let mut demands: Option<Vec<Option<u64>>> = None;
    let mut depot: Option<usize> = None;
    let mut i = 0;
    while i < lines.len() {
        let (ln, line) = lines[i];
        let toks = tokens(line, ln);
        let first = toks[0];
        i += 1;
        match first.text.to_ascii_uppercase().as_str() {
            "EOF" => break,
            "NODE_COORD_SECTION" => {
                let dim = h.dimension_for(&first)?;
                let mut v = vec![None; dim];
                for _ in 0..dim {
                    let (ln, line) = *lines
                        .get(i)
                        .ok_or_else(|| expected_eof(end_line, "a node line `id x y`"))?;
                    i += 1;
                    let t = tokens(line, ln);
                    let id = node_id(&t, 0, ln, line, dim, &v)?;
                    let x = number(&nth(&t, 1, ln, line, "an x coordinate")?, "an x coordinate")?;
                    let y = number(&nth(&t, 2, ln, line, "a y coordinate")?, "a y coordinate")?;
                    v[id] = Some((x, y));
                }
                coords = Some(v);
            }
            "DEMAND_SECTION" => {
                let dim = h.dimension_for(&first)?;
                let mut v = vec![None; dim];
                for _ in 0..dim {
                    let (ln, line) = *lines
                        .get(i)
                        .ok_or_else(|| expected_eof(end_line, "a demand line `id demand`"))?;
                    i += 1;
                    let t = tokens(line, ln);
                    let id = node_id(&t, 0, ln, line, dim, &v)?;
                    let d = nth(&t, 1, ln, line, "a demand")?;
                    v[id] = Some(unsigned(&d, "a demand (a non-negative integer)")?);
                }
                demands = Some(v);
            }
            "DEPOT_SECTION" => {
                let dim = h.dimension_for(&first)?;
                loop {
                    let (ln, line) = *lines
                        .get(i)
                        .ok_or_else(|| expected_eof(end_line, "a depot id or -1"))?;
                    i += 1;
                    let t = tokens(line, ln);
                    if t[0].text == "-1" {
                        break;
                    }
                    let id = unsigned(&t[0], "a depot id or -1")? as usize;
                    if id == 0 || id > dim {
                        return Err(invalid(
                            &t[0],
                            format!("depot {id} is not a node 1..={dim}"),
                        ));
                    }
                    if depot.is_some() {
                        return Err(ParseError::Unsupported {
                            line: ln,
                            column: t[0].column,
                            what: "second depot".to_string(),
                            found: t[0].text.to_string(),
                        });
                    }
                    depot = Some(id - 1);
                }
            }
            _ => h.read(ln, line, &first)?,
        }
    }
    let missing = |what: &str| expected_eof(end_line, what);
    let dim = h.dimension.ok_or_else(|| missing("a DIMENSION header"))?;
    let capacity = h.capacity.ok_or_else(|| missing("a CAPACITY header"))?;
    let coords = coords.ok_or_else(|| missing("a NODE_COORD_SECTION"))?;
    let demands = demands.ok_or_else(|| missing("a DEMAND_SECTION"))?;
    let depot = depot.ok_or_else(|| missing("a DEPOT_SECTION"))?;
    let mut order = vec![depot];
    order.extend((0..dim).filter(|&k| k != depot));
    let nodes = order
        .iter()
        .map(|&k| {
            // Every slot was filled: each section read exactly `dim` distinct ids.
            let (x, y) = coords[k].unwrap_or((0.0, 0.0));
            Node::untimed(x, y, demands[k].unwrap_or(0))
        })
        .collect();
    let name = h.name.unwrap_or_default();
    let vehicles = h.vehicles.or_else(|| fleet_from_name(&name));
    let mut inst = Instance::new(name, nodes, capacity, vehicles, Metric::RoundedEuclidean);
    inst.best_known = h.comment.as_deref().and_then(best_known_from_comment);
    Ok(inst)
}

#[derive(Default)]
struct Headers {
    name: Option<String>,
    comment: Option<String>,
    dimension: Option<usize>,
    capacity: Option<u64>,
    vehicles: Option<usize>,
}

impl Headers {
    fn dimension_for(&self, section: &Token<'_>) -> Result<usize, ParseError> {
        self.dimension.ok_or_else(|| ParseError::Expected {
            line: section.line,
            column: section.column,
            expected: "a DIMENSION header before this section".to_string(),
            found: format!("{:?}", section.text),
        })
    }

    /// One `KEY : value` line.
    fn read(&mut self, ln: usize, line: &str, first: &Token<'_>) -> Result<(), ParseError> {
        let Some(colon) = line.find(':') else {
            return Err(expected(first, "a `KEY : value` header or a section name"));
        };
        let key = line[..colon].trim().to_ascii_uppercase();
        let rest = &line[colon + 1..];
        let value = rest.trim();
        let lead = rest.len() - rest.trim_start().len();
        let column = line[..colon + 1 + lead].chars().count() + 1;
        let tok = Token {
            text: value,
            line: ln,
            column,
        };
        if value.is_empty() && key != "COMMENT" {
            return Err(expected_at_end(ln, line, "a value after the colon"));
        }
        match key.as_str() {
            "NAME" => self.name = Some(value.to_string()),
            "COMMENT" => self.comment = Some(value.to_string()),
            "TYPE" if !value.eq_ignore_ascii_case("CVRP") => {
                return Err(unsupported(&tok, "TYPE (only CVRP)"));
            }
            "EDGE_WEIGHT_TYPE" if !value.eq_ignore_ascii_case("EUC_2D") => {
                return Err(unsupported(&tok, "EDGE_WEIGHT_TYPE (only EUC_2D)"));
            }
            "DIMENSION" => {
                let d = unsigned(&tok, "a node count")?;
                if d < 1 {
                    return Err(invalid(&tok, "DIMENSION must count the depot".to_string()));
                }
                if d > MAX_NODES as u64 {
                    return Err(invalid(
                        &tok,
                        format!(
                            "DIMENSION {d} is more than the {} nodes the solvers take",
                            MAX_NODES
                        ),
                    ));
                }
                self.dimension =
                    Some(usize::try_from(d).map_err(|_| expected(&tok, "a node count"))?);
            }
            "CAPACITY" => self.capacity = Some(unsigned(&tok, "a capacity")?),
            "VEHICLES" => {
                let v = unsigned(&tok, "a vehicle count")?;
                self.vehicles =
                    Some(usize::try_from(v).map_err(|_| expected(&tok, "a vehicle count"))?);
            }
            _ => {}
        }
        Ok(())
    }
}

/// The 0-based node of a section line's id, checked against the range and earlier lines.
fn node_id<T>(
    t: &[Token<'_>],
    i: usize,
    ln: usize,
    line: &str,
    dim: usize,
    seen: &[Option<T>],
) -> Result<usize, ParseError> {
    let tok = nth(t, i, ln, line, "a node id")?;
    let id = unsigned(&tok, "a node id")? as usize;
    if id == 0 || id > dim {
        return Err(invalid(&tok, format!("node {id} is not in 1..={dim}")));
    }
    if seen[id - 1].is_some() {
        return Err(invalid(&tok, format!("node {id} is given twice")));
    }
    Ok(id - 1)
}

fn invalid(tok: &Token<'_>, message: String) -> ParseError {
    ParseError::Invalid {
        line: tok.line,
        column: tok.column,
        message,
    }
}

fn unsupported(tok: &Token<'_>, what: &str) -> ParseError {
    ParseError::Unsupported {
        line: tok.line,
        column: tok.column,
        what: what.to_string(),
        found: tok.text.to_string(),
    }
}

/// `k` of a CVRPLIB name like `A-n32-k5`.
fn fleet_from_name(name: &str) -> Option<usize> {
    let k = name.rsplit('-').next()?.strip_prefix(['k', 'K'])?;
    k.parse().ok()
}

/// The number after `value:` in a comment like `(Augerat et al, Optimal value: 784)`.
pub(crate) fn best_known_from_comment(comment: &str) -> Option<f64> {
    let lower = comment.to_ascii_lowercase();
    let at = lower.find("value:")? + "value:".len();
    let digits: String = comment[at..]
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    digits.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "NAME : t-n4-k2\nCOMMENT : (Optimal value: 12)\nTYPE : CVRP\n\
        DIMENSION : 4\nEDGE_WEIGHT_TYPE : EUC_2D\nCAPACITY : 10\nNODE_COORD_SECTION\n\
        1 0 0\n2 3 4\n3 0 1\n4 1 1\nDEMAND_SECTION\n1 5\n2 0\n3 2\n4 7\nDEPOT_SECTION\n2\n-1\nEOF\n";

    #[test]
    fn the_depot_becomes_node_zero_and_the_rest_keep_their_order() {
        let inst = parse_cvrplib(SMALL).unwrap();
        assert_eq!(inst.name, "t-n4-k2");
        assert_eq!(inst.vehicles, Some(2));
        assert_eq!(inst.best_known, Some(12.0));
        assert_eq!(inst.capacity, 10);
        let xy: Vec<_> = inst.nodes.iter().map(|n| (n.x, n.y, n.demand)).collect();
        assert_eq!(
            xy,
            vec![(3.0, 4.0, 0), (0.0, 0.0, 5), (0.0, 1.0, 2), (1.0, 1.0, 7)]
        );
        assert_eq!(inst.dist(0, 1), 5.0);
    }

    #[test]
    fn comments_give_best_known_values() {
        assert_eq!(
            best_known_from_comment("(Augerat et al, Min no of trucks: 5, Optimal value: 784)"),
            Some(784.0)
        );
        assert_eq!(best_known_from_comment("Best value: 1073.5)"), Some(1073.5));
        assert_eq!(best_known_from_comment("no number"), None);
    }
}
