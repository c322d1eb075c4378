//! The layout of a rail on sleepers over a deck meshed on its own (issue
//! 24): the rail's nodes where the scene puts them (at the deck's nodes,
//! or at the sleepers with a number of elements between two), the deck's
//! elements apart from the rail's, and each sleeper's ballast on the deck
//! at the sleeper's abscissa through the deck element's Hermite shape
//! functions (the consistent transfer of a point force, as a contact's).
//! The unknowns are numbered by abscissa, so the assembly stays a band
//! whose width is set by the longer of a deck and a rail element.

use crate::mesh::Mesh;
use crate::structure::rail_on_deck::{hermite, DeckElement, Seat, TrackLayout};

/// A sleeper within this fraction of a deck element of the element's end
/// rests at the end itself (its shape values then exactly 1 and 0): a
/// sleeper over a deck node loads that node alone, as before the rail
/// could be meshed at the sleepers.
const AT_NODE: f64 = 1e-9;

/// A rest of rail after the last whole element shorter than this fraction
/// of an element lengthens the last element rather than making its own
/// (an element orders of magnitude shorter than its neighbours would
/// leave the band's factor ill-conditioned).
const SHORTEST_REST: f64 = 0.1;

/// A rail's node abscissae, its element lengths and whether a sleeper
/// sits at each node.
type RailAtSleepers = (Vec<f64>, Vec<f64>, Vec<bool>);

/// The rail's nodes from `start` to `end`, their element lengths and
/// whether a sleeper sits at each: every `spacing` from `start`, with
/// `per_bay` equal elements between two sleepers; after the last whole
/// element, the rest in an element of its own, or (under a tenth of an
/// element) added to the last one, whose end node (and its sleeper, by
/// less than a tenth of an element) moves to `end`.
pub(super) fn rail_at_sleepers(
    (start, end): (f64, f64),
    spacing: f64,
    per_bay: usize,
) -> Result<RailAtSleepers, String> {
    if per_bay == 0 {
        return Err("track.on_deck.sleepers.rail_elements_per_bay = 0 must be >= 1".into());
    }
    let h = spacing / per_bay as f64;
    let whole = ((end - start) / h * (1.0 + 1e-12)).floor();
    // The count is bounded by the scene's rules (`scene::on_deck`).
    if !(h > 0.0 && whole.is_finite()) {
        return Err(format!(
            "spacing = {spacing:?} m in {per_bay} elements a bay gives {whole} rail elements \
             from {start} m to {end} m"
        ));
    }
    let whole = whole as usize;
    let mut node_x: Vec<f64> = (0..=whole).map(|k| start + k as f64 * h).collect();
    let mut lengths = vec![h; whole];
    let mut sleeper_at: Vec<bool> = (0..=whole).map(|k| k % per_bay == 0).collect();
    let rest = end - node_x[whole];
    if rest > SHORTEST_REST * h || (whole == 0 && rest > 0.0) {
        node_x.push(end);
        lengths.push(rest);
        sleeper_at.push(false);
    } else if rest > 0.0 {
        node_x[whole] = end;
        lengths[whole - 1] = end - node_x[whole - 1];
    }
    Ok((node_x, lengths, sleeper_at))
}

/// The layout of the rail at `node_x` (element `lengths`, sleepers where
/// `sleeper_at`) over the deck `mesh` on its own elements, whose lengths
/// are `deck_lengths`: the unknowns numbered by abscissa (at a shared
/// abscissa the rail's w, ψ, the sleeper's w, then the deck's), each
/// sleeper on the deck element under it (the one to its right at a
/// node) or on the ground.
pub(super) fn layout_apart(
    (node_x, lengths): (Vec<f64>, Vec<f64>),
    sleeper_at: &[bool],
    mesh: &Mesh,
    deck_lengths: &[f64],
) -> TrackLayout {
    let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    let (numbering, rail_dofs, sleeper_dofs, free) =
        number_by_abscissa(&node_x, mesh, sleeper_at, 1e-9 * shortest);
    let deck: Vec<DeckElement> = (0..mesh.element_dofs.len())
        .map(|k| DeckElement {
            start: mesh.element_start[k],
            end: mesh.element_end[k],
            length: deck_lengths[k],
            dofs: mesh.element_dofs[k].map(|d| d.map(|i| numbering[i])),
        })
        .collect();
    let element_dofs: Vec<[Option<usize>; 8]> = (0..node_x.len() - 1)
        .map(|e| {
            let (a, b) = (rail_dofs[e], rail_dofs[e + 1]);
            [
                Some(a[0]),
                Some(a[1]),
                None,
                None,
                Some(b[0]),
                Some(b[1]),
                None,
                None,
            ]
        })
        .collect();
    let on_deck = (node_x.windows(2))
        .map(|w| deck_at(&deck, 0.5 * (w[0] + w[1])).is_some())
        .collect();
    let seats: Vec<Seat> = (sleeper_dofs.iter().enumerate())
        .filter_map(|(node, dof)| {
            dof.map(|dof| Seat {
                node,
                dof,
                rail: rail_dofs[node][0],
                deck: deck_at(&deck, node_x[node]).map(|(k, s)| (k, hermite(s, deck[k].length))),
            })
        })
        .collect();
    let mut layout = TrackLayout {
        node_x,
        element_length: lengths,
        element_dofs,
        on_deck,
        rail_dofs,
        seats,
        deck,
        free,
        half_bandwidth: 0,
    };
    layout.half_bandwidth = half_bandwidth_apart(&layout);
    layout
}

/// The deck element under `x` and the abscissa s ∈ [0, 1] in it (the
/// element to the right at a node; within `AT_NODE` of an end, the end);
/// None off the deck.
pub(super) fn deck_at(deck: &[DeckElement], x: f64) -> Option<(usize, f64)> {
    let tolerance = |e: &DeckElement| AT_NODE * e.length;
    let k = deck
        .partition_point(|e| e.start <= x + tolerance(e))
        .checked_sub(1)?;
    let element = &deck[k];
    if x > element.end + tolerance(element) {
        return None;
    }
    let s = ((x - element.start) / element.length).clamp(0.0, 1.0);
    let s = if s < AT_NODE {
        0.0
    } else if s > 1.0 - AT_NODE {
        1.0
    } else {
        s
    };
    Some((k, s))
}

/// The widest reach of a rail element's DOFs, a deck element's, or a
/// sleeper's (its rail w, its own, the deck DOFs it loads).
fn half_bandwidth_apart(layout: &TrackLayout) -> usize {
    let reach = |dofs: &mut dyn Iterator<Item = usize>| {
        let (low, high) = dofs.fold((usize::MAX, 0), |(l, h), d| (l.min(d), h.max(d)));
        high.saturating_sub(low)
    };
    let rails = layout
        .element_dofs
        .iter()
        .map(|local| reach(&mut local.iter().flatten().copied()));
    let decks = (layout.deck.iter()).map(|e| reach(&mut e.dofs.iter().flatten().copied()));
    let seats = layout.seats.iter().map(|seat| {
        let base = layout.seat_base(seat).map(|(i, _)| i);
        reach(&mut [seat.rail, seat.dof].into_iter().chain(base))
    });
    rails.chain(decks).chain(seats).max().unwrap_or(0)
}

/// The deck DOFs' numbers in the assembly, the rail's (w, ψ) at each
/// node, the sleeper's DOF at each node (if any) and the count of free
/// DOFs.
type Numbering = (Vec<usize>, Vec<[usize; 2]>, Vec<Option<usize>>, usize);

/// Number the rail's, the sleepers' and the deck's DOFs by abscissa: at
/// each rail node, the deck's DOFs before it, then its w and ψ, the
/// sleeper's w where `sleeper_at`, then the deck's at its abscissa (within
/// `tolerance`); the deck's DOFs past the rail's last node last. The
/// deck mesh numbers its DOFs along the track, so its order is kept.
fn number_by_abscissa(
    node_x: &[f64],
    mesh: &Mesh,
    sleeper_at: &[bool],
    tolerance: f64,
) -> Numbering {
    let deck_x = mesh.free_dof_x();
    let mut numbering = vec![usize::MAX; mesh.free_dofs];
    let mut rail = Vec::with_capacity(node_x.len());
    let mut sleepers = vec![None; node_x.len()];
    let (mut next, mut d) = (0, 0);
    let mut take_deck_up_to = |limit: f64, next: &mut usize, d: &mut usize| {
        while *d < deck_x.len() && deck_x[*d] < limit {
            numbering[*d] = *next;
            *next += 1;
            *d += 1;
        }
    };
    for (node, &x) in node_x.iter().enumerate() {
        take_deck_up_to(x - tolerance, &mut next, &mut d);
        rail.push([next, next + 1]);
        next += 2;
        if sleeper_at[node] {
            sleepers[node] = Some(next);
            next += 1;
        }
        take_deck_up_to(x + tolerance, &mut next, &mut d);
    }
    take_deck_up_to(f64::INFINITY, &mut next, &mut d);
    (numbering, rail, sleepers, next)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rail_has_a_node_at_every_sleeper_and_ends_at_the_run_offs_end() {
        // 10 m at 0.6 m in two elements a bay: 33 elements of 0.3 m and a
        // rest of 0.1 m in an element of its own.
        let (x, lengths, at) = rail_at_sleepers((-2.0, 8.0), 0.6, 2).expect("meshes");
        assert_eq!(x.len(), 35);
        assert_eq!(x[34], 8.0);
        assert!((lengths[33] - 0.1).abs() < 1e-12);
        assert_eq!(at.iter().filter(|a| **a).count(), 17);
        assert!(at[0] && at[32] && !at[33] && !at[34]);
        // A rest of 0.01 m: the last element takes it.
        let (x, lengths, at) = rail_at_sleepers((0.0, 6.01), 0.6, 1).expect("meshes");
        assert_eq!((x.len(), x[10]), (11, 6.01));
        assert!((lengths[9] - 0.61).abs() < 1e-12 && at[10]);
    }

    #[test]
    fn a_sleeper_near_a_deck_node_rests_on_the_node_to_its_right() {
        let element = |start: f64| DeckElement {
            start,
            end: start + 1.0,
            length: 1.0,
            dofs: [None; 4],
        };
        let deck = [element(0.0), element(1.0), element(3.0)];
        assert_eq!(deck_at(&deck, 1.0 - 1e-12), Some((1, 0.0)));
        assert_eq!(deck_at(&deck, 2.0), Some((1, 1.0)));
        assert_eq!(deck_at(&deck, 0.25), Some((0, 0.25)));
        assert_eq!(deck_at(&deck, 2.5), None);
        assert_eq!(deck_at(&deck, -0.5), None);
    }
}
