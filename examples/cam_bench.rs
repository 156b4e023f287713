//! Times the arc fit of the paper's sample cam: `cargo run --release --example cam_bench`.

use std::time::Instant;

use ncsheet::geometry::cam::{fit_piece, Piece, PieceKind};

fn main() {
    let pieces = [
        (PieceKind::Archimedean, 79.0, 36.0, 102.0, 160.2),
        (PieceKind::Archimedean, 110.0, 10.8, 116.0, 25.2),
        (PieceKind::Logarithmic, 116.0, 25.2, 79.0, 28.0),
        (PieceKind::Logarithmic, 70.0, 340.0, 114.0, 360.0),
    ];
    for _ in 0..3 {
        let start = Instant::now();
        let mut n = 0;
        for (kind, r0, p0, r1, p1) in pieces {
            n += fit_piece(&Piece::new(kind, r0, p0, r1, p1).unwrap(), 0.001).unwrap().len();
        }
        println!("{n} arcs in {:?}", start.elapsed());
    }
}
