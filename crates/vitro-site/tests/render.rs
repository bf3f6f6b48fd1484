//! Rendering a hand-made site: the picture shows what is where.

use vitro_site::geo::Polygon;
use vitro_site::map::{Building, TownMap};
use vitro_site::render::{RenderOptions, render_map, render_site};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;

#[test]
fn a_building_is_drawn_where_it_stands() {
    let footprint = Polygon::new(
        vec![[-20.0, -10.0], [20.0, -10.0], [20.0, 10.0], [-20.0, 10.0]],
        vec![],
    )
    .unwrap();
    let map = TownMap::from_buildings(vec![Building {
        osm_id: 7,
        footprint,
        height: 12.0,
    }]);
    let terrain = Terrain::from_fn(40, 40, 10.0, |x, y| 0.05 * x + 0.02 * y).unwrap();
    let site = Site::new(map.clone(), terrain.clone(), &SiteConfig::default()).unwrap();
    let dir = std::env::temp_dir().join(format!("vitro-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("site.png");
    // A 200 x 200 m window around the building, 2 px per metre.
    let c = site.offset;
    let opts = RenderOptions {
        width: 400,
        window: Some([c[0] - 100.0, c[1] - 100.0, c[0] + 100.0, c[1] + 100.0]),
        ..RenderOptions::default()
    };
    let size = render_site(&site, &opts, &out).unwrap();
    assert_eq!((size.width, size.height), (400, 400));
    let png = tiny_skia::Pixmap::load_png(&out).unwrap();
    let px = |x: u32, y: u32| png.pixel(x, y).unwrap();
    // The building's middle is building-coloured (reddish brown), the ground away from it is not.
    let b = px(200, 200);
    assert!(b.red() > b.green() + 30 && b.red() > b.blue() + 30, "{b:?}");
    let g = px(330, 330);
    assert!(g.green() + 20 > g.red(), "{g:?}");
    // The forbidden buffer (2 m = 4 px) tints the ground just outside the wall (x = 40 + 2 px).
    let edge = px(200 + 40 + 2, 200);
    assert!(
        edge.red() > g.red() && edge.green() < g.green(),
        "{edge:?} vs {g:?}"
    );
    // The convenience entry point renders the whole town.
    let full = render_map(&map, &terrain, None, dir.join("full.png")).unwrap();
    assert!(full.width > 0 && full.height > 0);
    assert!(
        render_site(
            &site,
            &RenderOptions { width: 0, ..opts },
            dir.join("x.png")
        )
        .is_err()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
