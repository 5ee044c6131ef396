//! One mesh for every MPI rank: rank 0 alone makes it (Gmsh, the mesh cache, a mesh file),
//! and the other ranks receive it, bit for bit.
//!
//! Every rank of a parallel run holds the whole mesh (`problem/mod.rs`, "Parallel runs").
//! Made on rank 0 only, Gmsh runs once per mesh instead of once per rank (an adaptive run
//! remeshes at every step), the mesh cache and its files are touched by one process, and the
//! ranks cannot hold meshes that differ in round-off (a remeshing's size map is computed on
//! every rank from reduced sums). The mesh travels in the mesh cache's entry format
//! ([`super::cache::encode_entry`]: checksummed, validated on decoding), followed by one byte
//! for the order of a mesh file's triangles (0: none, 1: P1, 2: P2).
//!
//! Failures are agreed ([`Session::agree`]): rank 0's (the mesher's error, a bad mesh file)
//! before anything is sent, so that every other rank returns [`crate::Error::OtherRank`] and
//! rank 0 reports the error once; a receiving rank's (a message that does not decode) before
//! the ranks go on together.
use super::cache::{decode_entry, encode_entry};
use super::{Mesh, Order};
use crate::error::{Error, Result};
use crate::petsc::Session;

/// The key the message is encoded with (an entry of no cache).
const KEY: &str = "signorini mesh sent from MPI rank 0";

/// `make` on rank 0, its mesh (and the order of a mesh file's triangles) on every rank; the
/// value of `make` is returned unchanged on rank 0. Collective: every rank calls it at the
/// same point; `make` runs on rank 0 only. On a single process, `make`.
pub fn from_rank_0(
    session: &Session,
    during: &'static str,
    make: impl FnOnce() -> Result<(Mesh, Option<Order>)>,
) -> Result<(Mesh, Option<Order>)> {
    if session.size() == 1 {
        return make();
    }
    if session.rank() == 0 {
        let made = make().and_then(|(mesh, file_order)| {
            let mut bytes = encode_entry(KEY, &mesh)
                .map_err(|e| Error::mesh("mesh", format!("encoding the mesh for the other MPI ranks: {e}")))?;
            bytes.push(order_byte(file_order));
            Ok((mesh, file_order, bytes))
        });
        let (mesh, file_order, bytes) = session.agree(made, during)?;
        session.world().broadcast_from_rank_0(bytes)?;
        session.agree(Ok(()), during)?;
        return Ok((mesh, file_order));
    }
    session.agree(Ok(()), during)?; // rank 0's outcome: Error::OtherRank if it failed
    let bytes = session.world().broadcast_from_rank_0(Vec::new())?;
    let received = match bytes.split_last() {
        Some((&order, entry)) => decode_entry(entry, KEY)
            .and_then(|mesh| Ok((mesh, byte_order(order).ok_or("an unknown order byte")?)))
            .map_err(|e| Error::mesh("mesh", format!("the mesh received from MPI rank 0: {e}"))),
        None => Err(Error::mesh("mesh", "the mesh received from MPI rank 0 is empty")),
    };
    session.agree(received, during)
}

fn order_byte(order: Option<Order>) -> u8 {
    match order {
        None => 0,
        Some(Order::P1) => 1,
        Some(Order::P2) => 2,
    }
}

fn byte_order(byte: u8) -> Option<Option<Order>> {
    match byte {
        0 => Some(None),
        1 => Some(Some(Order::P1)),
        2 => Some(Some(Order::P2)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_bytes_round_trip() {
        for order in [None, Some(Order::P1), Some(Order::P2)] {
            assert_eq!(byte_order(order_byte(order)), Some(order));
        }
        assert_eq!(byte_order(3), None);
    }
}
