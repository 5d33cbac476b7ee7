//! Command-line arguments (DESIGN.md, "Command line").

use clap::builder::PossibleValue;
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::sync::LazyLock;

/// demkit: density-equalizing maps (area-preserving parameterizations, cartograms, lenses)
/// of triangulated surfaces.
#[derive(Parser, Debug)]
#[command(name = "demkit", version, about, long_about = None, allow_negative_numbers = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
#[allow(clippy::large_enum_variant)] // parsed once; boxing would only add noise
pub enum Command {
    /// Print a mesh's counts, topology and validation findings.
    Info(InfoArgs),
    /// Compute a density-equalizing map and write the mapped mesh.
    Map(MapArgs),
    /// Write a synthetic mesh (grids, polygons, height fields, spheres, tori, ...).
    Generate(GenerateArgs),
    /// Remesh a surface through its density-equalizing map (uniform or population-driven).
    Remesh(RemeshArgs),
    /// Make a cartogram of GeoJSON regions: each region's area proportional to a value.
    Cartogram(CartogramArgs),
    /// Carry one genus-0 surface onto another through landmark-matched spherical maps.
    Register(RegisterArgs),
    /// Draw a mesh to a PNG picture.
    Render(RenderArgs),
    /// Split every triangle into four at its edge midpoints (the same surface, finer).
    Subdivide(SubdivideArgs),
    /// Cut holes into a surface around given points (for DEQ and the circle-domain map).
    Cut(CutArgs),
    /// Time `demkit map` on a suite of meshes: iterations, accuracy and peak memory per case.
    Bench(BenchArgs),
    /// `demkit map` that also prints its peak resident memory on stdout: how `demkit bench`
    /// runs each case.
    #[command(name = "bench-map", hide = true)]
    BenchMap(MapArgs),
}

/// `demkit info MESH [--json]`
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The mesh (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `--method`: a method of the library, as clap reads and lists it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MethodArg(pub demkit::Method);

static METHODS: LazyLock<Vec<MethodArg>> =
    LazyLock::new(|| demkit::Method::ALL.iter().map(|&m| MethodArg(m)).collect());

impl ValueEnum for MethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        &METHODS
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.0.name()).help(self.0.summary()))
    }
}

/// How a density-equalizing map is computed: the options shared by `map` and `remesh`.
#[derive(Args, Debug, Clone)]
pub struct MethodArgs {
    /// The method.
    #[arg(long, value_enum, default_value = "auto")]
    pub method: MethodArg,
    /// `area`, `uniform`, a FILE with one value per face, or an expression of x, y, z, area.
    #[arg(long, default_value = "area", allow_hyphen_values = true)]
    pub population: String,
    /// Landmark file: `vertex_index target_x target_y [target_z]` per line.
    #[arg(long)]
    pub landmarks: Option<PathBuf>,
    /// Target shape for dem-shape: disk, square, rectangle:W:H, ellipse:A:B.
    #[arg(long)]
    pub shape: Option<String>,
    /// Target torus radii R:r (tdem).
    #[arg(long, allow_hyphen_values = true)]
    pub torus: Option<String>,
    /// Target ellipsoid radii A:B:C along x, y, z (edem; edeq's initial guess, default from the
    /// surface's extents; with `--method auto` a genus-0 closed surface is then mapped by edem).
    #[arg(long, allow_hyphen_values = true)]
    pub ellipsoid: Option<String>,
    /// The energy weights.
    #[command(flatten)]
    pub weights: WeightArgs,
    /// Keep the holes' centres and radii (deq, ldeq): the shape-preserving variant.
    #[arg(long)]
    pub no_geometry_update: bool,
    /// Time step (default: the method's own choice).
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// When the iteration stops.
    #[command(flatten)]
    pub stop: StopArgs,
}

/// The energy weights of LSDEM (`map --method lsdem`, `register`) and DEQ/LDEQ (α only).
#[derive(Args, Debug, Clone)]
pub struct WeightArgs {
    /// Energy weight α: the density term (lsdem, register); the weight of mean |μ| against the
    /// density (deq, ldeq); of Σ|μ|² against the density gradient (edeq). Default: the method's
    /// paper value.
    #[arg(long, allow_hyphen_values = true)]
    pub alpha: Option<f64>,
    /// Energy weight β of the harmonic term (lsdem, register; default: the paper's).
    #[arg(long, allow_hyphen_values = true)]
    pub beta: Option<f64>,
    /// Energy weight γ of the landmark term (lsdem, register; default: the paper's).
    #[arg(long, allow_hyphen_values = true)]
    pub gamma: Option<f64>,
}

/// When an iteration stops: its tolerance and its limit.
#[derive(Args, Debug, Clone)]
pub struct StopArgs {
    /// Stopping tolerance (default: the method's paper value).
    #[arg(long, allow_hyphen_values = true)]
    pub epsilon: Option<f64>,
    /// Iteration limit (default: the method's own).
    #[arg(long, allow_hyphen_values = true)]
    pub max_iter: Option<usize>,
}

/// `demkit map MESH --out OUT [...]`
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct MapArgs {
    /// The input mesh (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Output mesh (.obj or .ply): same faces and vertex order, mapped coordinates.
    #[arg(long)]
    pub out: PathBuf,
    /// The method and its parameters.
    #[command(flatten)]
    pub m: MethodArgs,
    /// Write the JSON report here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Also write the input mesh with texture coordinates (`vt`, in [0, 1]²) from the planar,
    /// circle-domain or flat-torus map (.obj).
    #[arg(long = "uv-out")]
    pub uv_out: Option<PathBuf>,
    /// Also draw the input coloured by its population density beside the map coloured by the
    /// density left after it, with a checkerboard carried from the initial map (.png).
    #[arg(long)]
    pub render: Option<PathBuf>,
    /// Also draw the initial and final density histograms side by side (.png).
    #[arg(long)]
    pub histogram: Option<PathBuf>,
    /// How pictures are drawn.
    #[command(flatten)]
    pub picture: PictureArgs,
    /// No progress bar and no warnings.
    #[arg(long)]
    pub quiet: bool,
}

/// The view and size of pictures (`map --render/--histogram`, `render`).
#[derive(Args, Debug)]
pub struct PictureArgs {
    /// AZIMUTH:ELEVATION in degrees, z up (default: -60:30, or -90:60 for surfaces flattest
    /// along z); planar meshes and maps are drawn flat from above unless this is given.
    #[arg(long, allow_hyphen_values = true)]
    pub view: Option<String>,
    /// Picture height in pixels (64 to 4096); histograms are 1.5 times as wide; `map
    /// --render` draws two N × N pictures side by side, each with a legend strip.
    #[arg(
        long,
        default_value_t = 1024,
        allow_negative_numbers = true,
        allow_hyphen_values = true
    )]
    pub size: i64,
}

/// `demkit remesh MESH --out OUT [--vertices N] [method options]`
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct RemeshArgs {
    /// The input mesh (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Output mesh (.obj or .ply): a new triangulation of the input surface.
    #[arg(long)]
    pub out: PathBuf,
    /// About how many vertices the new mesh has.
    #[arg(long, default_value_t = 5000, allow_hyphen_values = true)]
    pub vertices: usize,
    /// The map used for remeshing and its parameters; the population sets the vertex density.
    #[command(flatten)]
    pub m: MethodArgs,
    /// Write a JSON report (the map's and the new mesh's figures) here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// No progress bar and no warnings.
    #[arg(long)]
    pub quiet: bool,
}

/// `demkit cartogram REGIONS.geojson --value FIELD --out OUT.geojson [...]`
#[derive(Args, Debug)]
pub struct CartogramArgs {
    /// The regions: a GeoJSON FeatureCollection of polygons and multipolygons.
    pub regions: PathBuf,
    /// The numeric feature property that sets each region's area; with --values, the CSV
    /// column holding the values (default: the CSV's only column besides --key). A missing
    /// value (no property, null, no CSV row) gets the mean density of the others (value per
    /// area) times the region's area; a value of 0 gets 0.2 times the smallest positive value;
    /// a warning names those regions. Negative values are refused.
    #[arg(long, required_unless_present = "values")]
    pub value: Option<String>,
    /// Read the values from this CSV file (first row a header) instead of a feature property,
    /// joined to the features on --key.
    #[arg(long, value_name = "FILE.csv", requires = "key")]
    pub values: Option<PathBuf>,
    /// The join key of --values: a CSV column and a feature property holding the same names
    /// or codes.
    #[arg(long, value_name = "NAME", requires = "values")]
    pub key: Option<String>,
    /// Output GeoJSON: the same features and properties, transformed coordinates.
    #[arg(long)]
    pub out: PathBuf,
    /// Also draw the cartogram as SVG, regions coloured as --color says, with a legend.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Also draw the cartogram as a PNG picture, coloured as --color says, with a legend.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// What colours the regions of --svg and --png: `density` (the value per input area, on a
    /// logarithmic scale) or `error` (each region's share error, blue too small, red too
    /// large).
    #[arg(long, value_enum, default_value = "density")]
    pub color: CartogramColor,
    /// The PNG picture's longer side in pixels (64 to 4096).
    #[arg(
        long,
        default_value_t = 1024,
        allow_negative_numbers = true,
        allow_hyphen_values = true
    )]
    pub size: i64,
    /// Write a JSON report here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Coordinates are longitude/latitude degrees: compute on the globe (the flow in an
    /// equal-area projection) and write degrees.
    #[arg(long, conflicts_with = "project")]
    pub sphere: bool,
    /// Coordinates are longitude/latitude degrees: project them to the Equal Earth projection
    /// (km) and compute the planar cartogram there; the output is in that projection unless
    /// --output-lonlat.
    #[arg(long)]
    pub project: bool,
    /// With --project, write the output back in longitude/latitude degrees.
    #[arg(long, requires = "project")]
    pub output_lonlat: bool,
    /// The accuracy asked for: every region with at least 1e-4 of the total value within this
    /// relative error of its share (exit 3 otherwise).
    #[arg(
        allow_hyphen_values = true,
        long,
        value_name = "E",
        default_value_t = 0.01,
        allow_negative_numbers = true
    )]
    pub max_error: f64,
    /// No further round starts after this many seconds (default: no limit).
    #[arg(
        long,
        value_name = "SECONDS",
        allow_negative_numbers = true,
        allow_hyphen_values = true
    )]
    pub time_limit: Option<f64>,
    /// The flow's grid: cells along the map's longer side, a power of two from 16 to 8192
    /// (finer is more accurate for small regions and slower).
    #[arg(
        allow_hyphen_values = true,
        long,
        value_name = "N",
        default_value_t = 1024,
        allow_negative_numbers = true
    )]
    pub grid: usize,
    /// Integration steps per round (default: the method's own).
    #[arg(long, allow_hyphen_values = true)]
    pub max_iter: Option<usize>,
    /// No progress bar and no warnings.
    #[arg(long)]
    pub quiet: bool,
}

/// `--color` of `demkit cartogram`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CartogramColor {
    /// The value per input area, logarithmic.
    Density,
    /// The share error of each region.
    Error,
}

/// `demkit register A B --landmarks-a FA --landmarks-b FB --out OUT.obj`
#[derive(Args, Debug)]
pub struct RegisterArgs {
    /// The surface to carry over (genus-0 closed).
    pub a: PathBuf,
    /// The surface to land on (genus-0 closed).
    pub b: PathBuf,
    /// A's landmarks: one vertex index per line.
    #[arg(long = "landmarks-a")]
    pub landmarks_a: PathBuf,
    /// B's landmarks, corresponding line by line to A's.
    #[arg(long = "landmarks-b")]
    pub landmarks_b: PathBuf,
    /// Output mesh (.obj or .ply): A's faces, vertices on B's surface.
    #[arg(long)]
    pub out: PathBuf,
    /// LSDEM's energy weights.
    #[command(flatten)]
    pub weights: WeightArgs,
    /// When LSDEM stops.
    #[command(flatten)]
    pub stop: StopArgs,
    /// Write a JSON report here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// No progress bar and no warnings.
    #[arg(long)]
    pub quiet: bool,
}

/// `demkit render MESH --out PNG [--color FILE]`
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The mesh (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Output picture (.png).
    #[arg(long)]
    pub out: PathBuf,
    /// One value per face (population-file format) to colour by; default: plain shading.
    #[arg(long)]
    pub color: Option<PathBuf>,
    /// How the picture is drawn.
    #[command(flatten)]
    pub picture: PictureArgs,
    /// No warnings about the mesh.
    #[arg(long)]
    pub quiet: bool,
}

/// `demkit generate KIND ... --out FILE`
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct GenerateArgs {
    #[command(subcommand)]
    pub kind: GenerateKind,
    /// Output mesh (.obj or .ply).
    #[arg(long, global = true)]
    pub out: Option<PathBuf>,
}

/// The generated mesh kinds.
#[derive(Subcommand, Debug)]
pub enum GenerateKind {
    /// A planar grid of nx × ny squares, each split into two triangles, on [0,W]×[0,H].
    #[command(allow_negative_numbers = true)]
    Grid {
        #[arg(long, default_value_t = 99, allow_hyphen_values = true)]
        nx: usize,
        #[arg(long, default_value_t = 99, allow_hyphen_values = true)]
        ny: usize,
        #[arg(long, default_value_t = 99.0, allow_hyphen_values = true)]
        width: f64,
        #[arg(long, default_value_t = 99.0, allow_hyphen_values = true)]
        height: f64,
    },
    /// A regular polygon of circumradius 1 triangulated by concentric rings.
    #[command(allow_negative_numbers = true)]
    Polygon {
        #[arg(long, default_value_t = 6, allow_hyphen_values = true)]
        sides: usize,
        #[arg(long, default_value_t = 32, allow_hyphen_values = true)]
        rings: usize,
    },
    /// MATLAB's peaks surface on [-3,3]², n × n squares.
    #[command(allow_negative_numbers = true)]
    Peaks {
        #[arg(long, default_value_t = 45, allow_hyphen_values = true)]
        n: usize,
    },
    /// A Gaussian bump on [0,1]², n × n squares.
    #[command(allow_negative_numbers = true)]
    Gaussian {
        #[arg(long, default_value_t = 72, allow_hyphen_values = true)]
        n: usize,
    },
    /// A planar annulus.
    #[command(allow_negative_numbers = true)]
    Annulus {
        #[arg(long, default_value_t = 0.4, allow_hyphen_values = true)]
        inner: f64,
        #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
        outer: f64,
        #[arg(long, default_value_t = 12, allow_hyphen_values = true)]
        radial: usize,
        #[arg(long, default_value_t = 96, allow_hyphen_values = true)]
        angular: usize,
    },
    /// The unit disk minus circular holes, each given as cx:cy:r.
    #[command(allow_negative_numbers = true)]
    DiskHoles {
        /// A circular hole CX:CY:R; repeat the option for several holes.
        #[arg(long = "hole", value_name = "CX:CY:R", allow_hyphen_values = true)]
        holes: Vec<String>,
        #[arg(long, default_value_t = 40, allow_hyphen_values = true)]
        resolution: usize,
    },
    /// The rectangle [-W/2,W/2]×[-H/2,H/2] minus circular holes, each given as cx:cy:r.
    #[command(allow_negative_numbers = true)]
    RectHoles {
        #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
        width: f64,
        #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
        height: f64,
        /// A circular hole CX:CY:R; repeat the option for several holes.
        #[arg(long = "hole", value_name = "CX:CY:R", allow_hyphen_values = true)]
        holes: Vec<String>,
        /// Boundary points along the longer side.
        #[arg(long, default_value_t = 40, allow_hyphen_values = true)]
        resolution: usize,
    },
    /// A subdivided icosahedron on the unit sphere.
    #[command(allow_negative_numbers = true)]
    Icosphere {
        #[arg(long, default_value_t = 4, allow_hyphen_values = true)]
        subdivisions: usize,
    },
    /// A latitude/longitude sphere.
    #[command(allow_negative_numbers = true)]
    UvSphere {
        #[arg(long, default_value_t = 32, allow_hyphen_values = true)]
        lat: usize,
        #[arg(long, default_value_t = 64, allow_hyphen_values = true)]
        lon: usize,
    },
    /// A torus with radii R > r.
    #[command(allow_negative_numbers = true)]
    Torus {
        #[arg(long = "R", default_value_t = 2.0, allow_hyphen_values = true)]
        big_r: f64,
        #[arg(long = "r", default_value_t = 1.0, allow_hyphen_values = true)]
        small_r: f64,
        #[arg(long, default_value_t = 64, allow_hyphen_values = true)]
        major: usize,
        #[arg(long, default_value_t = 32, allow_hyphen_values = true)]
        minor: usize,
    },
}

/// `demkit subdivide MESH --out OUT [--levels N] [--parts K] [--population FILE --population-out FILE]`
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct SubdivideArgs {
    /// The input mesh (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Output mesh (.obj or .ply): the input vertices first, then the points on the edges,
    /// then those inside the faces; face f becomes faces M·f to M·(f+1) − 1, M = (K²)^N.
    #[arg(long)]
    pub out: PathBuf,
    /// How many rounds of subdivision (N rounds: (K²)^N times the faces).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub levels: usize,
    /// Into how many equal parts every edge is cut in a round (K: every triangle becomes K²;
    /// 2 is midpoint subdivision).
    #[arg(long, default_value_t = 2, allow_hyphen_values = true)]
    pub parts: usize,
    /// A population file of the input (one value per face), to split among the new faces.
    #[arg(long, value_name = "FILE", requires = "population_out")]
    pub population: Option<PathBuf>,
    /// Where the split population goes: every input value divided equally among its (K²)^N
    /// faces, one value per line.
    #[arg(long, value_name = "FILE", requires = "population")]
    pub population_out: Option<PathBuf>,
    /// No summary line and no warnings.
    #[arg(long)]
    pub quiet: bool,
}

/// `demkit cut MESH --hole X,Y,Z,R [--hole ...] [--planar] --out OUT [--quiet]`
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct CutArgs {
    /// The input mesh (.obj, .ply, .off, .stl).
    pub mesh: PathBuf,
    /// Output mesh (.obj or .ply): the faces outside every hole, the vertices they use in
    /// their input order.
    #[arg(long)]
    pub out: PathBuf,
    /// A hole: every face whose centroid lies within R of the point (X, Y, Z) is removed
    /// (repeat for several holes).
    #[arg(
        long,
        value_name = "X,Y,Z,R",
        required = true,
        allow_hyphen_values = true
    )]
    pub hole: Vec<String>,
    /// Measure the distance to a hole's centre in the plane z = 0 (a cylinder through the
    /// surface instead of a ball).
    #[arg(long)]
    pub planar: bool,
    /// No summary line and no warnings.
    #[arg(long)]
    pub quiet: bool,
}

/// `demkit bench [--data DIR] [--scale] [--filter TEXT] [--json FILE]`
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct BenchArgs {
    /// The papers' meshes (genus0/, genus1/, open/): adds the real-mesh cases. Default: the
    /// directory in DEMKIT_DATA, when that is set.
    #[arg(long, value_name = "DIR")]
    pub data: Option<PathBuf>,
    /// Adds the large cases: meshes of 0.3 to 1.5 million faces, among them the real ones
    /// subdivided (with --data), for time and memory against size.
    #[arg(long)]
    pub scale: bool,
    /// Runs only the cases whose name contains TEXT (repeat for several).
    #[arg(long, value_name = "TEXT")]
    pub filter: Vec<String>,
    /// Also writes the results as JSON here.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Caps every case's iterations (default: each method's own limit); a case stopped by it is
    /// shown as not converged.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub max_iter: Option<usize>,
    /// Lists the cases (name, mesh, method, population) without running them.
    #[arg(long)]
    pub list: bool,
}
