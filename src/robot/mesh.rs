//! Mesh collision geometry: where a URDF's `<mesh filename=…>` is, reading it (STL ASCII and
//! binary, COLLADA, OBJ through the `mesh-loader` crate), bounds, and its exact convex hull.
//!
//! # Resolution
//! A mesh filename is resolved, in this order:
//! - `package://NAME/REST`: for each package directory `D` (the `--package-path` flags in
//!   order, then each entry of `ROS_PACKAGE_PATH`), `D/NAME/REST`, then `D/REST` when `D`'s own
//!   name is `NAME` (a package directory given directly). The first existing file wins.
//! - `file:///abs/path`: that path.
//! - anything else: relative to the URDF file's directory (absolute paths as they are).
//!
//! A mesh that resolves nowhere is an error listing every path searched.
//!
//! # Bounds
//! A mesh file larger than [`MAX_MESH_FILE_BYTES`] is an
//! error before it is read (a 2-million-triangle binary STL is 100 MB), and so is a mesh with
//! more than [`MAX_MESH_TRIANGLES`] triangles, so memory
//! stays bounded. An empty mesh, a non-finite vertex, a non-positive or non-finite `scale`, an
//! unsupported format and a flat (zero-volume) mesh are errors too.
//!
//! # Hull
//! Collision uses the mesh's convex hull (parry's quickhull, [`ConvexPolyhedron`]): it contains
//! every vertex, so a contact of the meshes is always a contact of their hulls (the hull may
//! report contacts in concavities that the mesh does not have; never the reverse). The
//! triangles are kept for the exact mesh–mesh reference of the tests
//! ([`LoadedMesh::trimesh`]). A capsule containing the hull and every vertex is fitted at load
//! ([`LoadedMesh::capsule`], [`fit`](crate::robot::collision::fit)): the fast primitive layer.

use crate::error::{Error, Result};
use crate::limits::{MAX_MESH_FILE_BYTES, MAX_MESH_TRIANGLES};
use crate::math::{Real, Vec3};
use parry3d_f64::shape::{ConvexPolyhedron, SharedShape, TriMesh};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where mesh files are looked for (see the module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshSearch {
    /// Package directories, searched in order before `ROS_PACKAGE_PATH`.
    pub package_paths: Vec<PathBuf>,
    /// Also search the entries of the `ROS_PACKAGE_PATH` environment variable.
    pub ros_package_path: bool,
}

impl MeshSearch {
    /// The given directories, then `ROS_PACKAGE_PATH`.
    pub fn new(package_paths: Vec<PathBuf>) -> MeshSearch {
        MeshSearch {
            package_paths,
            ros_package_path: true,
        }
    }

    /// Every package directory searched, in order.
    pub fn package_dirs(&self) -> Vec<PathBuf> {
        let mut dirs = self.package_paths.clone();
        if self.ros_package_path {
            if let Some(v) = std::env::var_os("ROS_PACKAGE_PATH") {
                dirs.extend(std::env::split_paths(&v).filter(|p| !p.as_os_str().is_empty()));
            }
        }
        dirs
    }

    /// The candidate paths of `filename` (see the module docs), in search order.
    pub fn candidates(&self, filename: &str, urdf_dir: Option<&Path>) -> Vec<PathBuf> {
        if let Some(rest) = filename.strip_prefix("package://") {
            let (pkg, tail) = rest.split_once('/').unwrap_or((rest, ""));
            let mut out = Vec::new();
            for d in self.package_dirs() {
                out.push(d.join(pkg).join(tail));
                if d.file_name().is_some_and(|n| n == pkg) {
                    out.push(d.join(tail));
                }
            }
            out
        } else if let Some(abs) = filename.strip_prefix("file://") {
            vec![PathBuf::from(abs)]
        } else {
            let p = Path::new(filename);
            match urdf_dir {
                Some(d) if p.is_relative() => vec![d.join(p)],
                _ => vec![p.to_path_buf()],
            }
        }
    }

    /// The first existing candidate of `filename`; else an error naming `what`, the filename
    /// and every path searched.
    pub fn resolve(&self, filename: &str, urdf_dir: Option<&Path>, what: &str) -> Result<PathBuf> {
        let cands = self.candidates(filename, urdf_dir);
        if let Some(p) = cands.iter().find(|p| p.is_file()) {
            return Ok(p.clone());
        }
        let searched = if cands.is_empty() {
            "no package directory given (--package-path DIR, or ROS_PACKAGE_PATH)".to_string()
        } else {
            format!(
                "searched {}",
                cands
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        Err(Error::invalid(
            what,
            filename,
            format!("mesh file not found: {searched}"),
        ))
    }
}

/// A mesh read from a file, scaled, with its convex hull.
#[derive(Clone)]
pub struct LoadedMesh {
    /// The file read.
    pub file: PathBuf,
    /// The file and the digest of its contents.
    pub source: crate::sources::SourceFile,
    /// Vertices (scaled; the mesh's own frame, i.e. the collision element's origin frame).
    pub vertices: Vec<Vec3>,
    /// Triangles (indices into `vertices`).
    pub triangles: Vec<[u32; 3]>,
    /// The convex hull as a parry shape.
    pub hull: SharedShape,
    /// The hull's vertices.
    pub hull_points: Vec<Vec3>,
    /// A capsule containing the hull and every vertex, with its gap
    /// ([`fit_capsule`](crate::robot::collision::fit::fit_capsule)).
    pub capsule: crate::robot::collision::fit::FittedCapsule,
}

impl std::fmt::Debug for LoadedMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedMesh")
            .field("file", &self.file)
            .field("vertices", &self.vertices.len())
            .field("triangles", &self.triangles.len())
            .field("hull_points", &self.hull_points.len())
            .field("capsule", &self.capsule)
            .finish()
    }
}

impl LoadedMesh {
    /// The mesh as a parry triangle mesh (the exact reference shape; built on demand).
    pub fn trimesh(&self) -> Result<TriMesh> {
        TriMesh::new(
            self.vertices.iter().map(|v| (*v).into()).collect(),
            self.triangles.clone(),
        )
        .map_err(|e| Error::File {
            path: self.file.clone(),
            reason: format!("not a valid triangle mesh: {e:?}"),
        })
    }

    /// The hull as a parry convex polyhedron.
    pub fn hull_polyhedron(&self) -> &ConvexPolyhedron {
        self.hull
            .as_convex_polyhedron()
            .expect("hull is a convex polyhedron")
    }
}

/// Read `path` (format by extension or content, as mesh-loader detects it), scale it by
/// `scale` (per axis) and build its hull. `what` names the element in errors (`link L
/// collision[i]`).
pub fn load(path: &Path, scale: [Real; 3], what: &str) -> Result<LoadedMesh> {
    let err = |reason: String| Error::File {
        path: path.to_path_buf(),
        reason: format!("{what}: {reason}"),
    };
    if !scale.iter().all(|s| s.is_finite() && *s > 0.0) {
        return Err(Error::invalid(
            format!("{what} mesh scale"),
            format!("{scale:?}"),
            "must be finite and > 0 per axis",
        ));
    }
    let meta = std::fs::metadata(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if meta.len() > MAX_MESH_FILE_BYTES {
        return Err(err(format!(
            "mesh file of {} bytes exceeds the limit of {} bytes (helixreach::limits::MAX_MESH_FILE_BYTES); decimate it or give a simpler collision mesh",
            meta.len(),
            MAX_MESH_FILE_BYTES
        )));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !matches!(ext.as_str(), "stl" | "dae" | "obj") {
        return Err(err(format!(
            "unsupported mesh format {:?} (supported: .stl, .dae, .obj)",
            path.extension()
                .map(|e| e.to_string_lossy().into_owned())
                .unwrap_or_default()
        )));
    }
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    // Binary STL declares its triangle count in its header: refuse a huge one before parsing.
    if ext == "stl" && bytes.len() >= 84 && !bytes.starts_with(b"solid") {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if n > MAX_MESH_TRIANGLES {
            return Err(err(format!(
                "{n} triangles exceed the limit of {MAX_MESH_TRIANGLES} (helixreach::limits::MAX_MESH_TRIANGLES)"
            )));
        }
    }
    let scene = mesh_loader::Loader::default()
        .merge_meshes(true)
        .load_from_slice(&bytes, path)
        .map_err(|e| err(format!("cannot read the mesh: {e}")))?;
    let source = crate::sources::SourceFile::from_bytes(&path.display().to_string(), &bytes);
    drop(bytes);
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for m in &scene.meshes {
        if triangles.len() + m.faces.len() > MAX_MESH_TRIANGLES {
            return Err(err(format!(
                "more than {MAX_MESH_TRIANGLES} triangles (helixreach::limits::MAX_MESH_TRIANGLES)"
            )));
        }
        let base = vertices.len() as u32;
        for (k, v) in m.vertices.iter().enumerate() {
            if !v.iter().all(|x| x.is_finite()) {
                return Err(err(format!("vertex {k} is not finite: {v:?}")));
            }
            vertices.push(Vec3::new(
                Real::from(v[0]) * scale[0],
                Real::from(v[1]) * scale[1],
                Real::from(v[2]) * scale[2],
            ));
        }
        for f in &m.faces {
            if f.iter().any(|&i| i as usize >= m.vertices.len()) {
                return Err(err(format!("face {f:?} names a vertex past the end")));
            }
            triangles.push([f[0] + base, f[1] + base, f[2] + base]);
        }
    }
    if triangles.is_empty() {
        return Err(err("empty mesh (no triangles)".into()));
    }
    let pts: Vec<parry3d_f64::math::Point<Real>> = vertices.iter().map(|v| (*v).into()).collect();
    let hull = ConvexPolyhedron::from_convex_hull(&pts).ok_or_else(|| {
        err("no convex hull (the mesh is flat or degenerate: it encloses no volume)".into())
    })?;
    // parry returns a flat "hull" for coplanar points: require a volume (relative to the size).
    let hull_points: Vec<Vec3> = hull.points().iter().map(|p| p.coords).collect();
    let size = hull_points
        .iter()
        .map(|p| (p - hull_points[0]).norm())
        .fold(0.0, Real::max);
    let volume = {
        use parry3d_f64::shape::Shape as _;
        hull.mass_properties(1.0).mass()
    };
    if hull_points.len() < 4 || volume.is_nan() || volume <= 1e-9 * size * size * size {
        return Err(err(
            "no convex hull (the mesh is flat or degenerate: it encloses no volume)".into(),
        ));
    }
    let capsule = crate::robot::collision::fit::fit_capsule(&hull, &hull_points, &vertices);
    Ok(LoadedMesh {
        file: path.to_path_buf(),
        source,
        vertices,
        triangles,
        hull: SharedShape::new(hull),
        hull_points,
        capsule,
    })
}

/// A loaded mesh shared by every element that names the same file and scale.
pub(crate) type MeshCache = std::collections::HashMap<(PathBuf, [u64; 3]), Arc<LoadedMesh>>;

/// [`load`] through a cache keyed by the path and the scale's bits.
pub(crate) fn load_cached(
    cache: &mut MeshCache,
    path: &Path,
    scale: [Real; 3],
    what: &str,
) -> Result<Arc<LoadedMesh>> {
    let key = (path.to_path_buf(), scale.map(f64::to_bits));
    if let Some(m) = cache.get(&key) {
        return Ok(m.clone());
    }
    let m = Arc::new(load(path, scale, what)?);
    cache.insert(key, m.clone());
    Ok(m)
}
