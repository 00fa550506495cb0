#include "apps/scene_vtk_links.h"

#include "fem/atomic_file.h"
#include "multibody/spatial.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkCubeSource.h>
#include <vtkCylinderSource.h>
#include <vtkExecutive.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkTypeInt32Array.h>
#include <vtkXMLPolyDataWriter.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace plantar::app {
namespace {

constexpr int n_sides = 16;        // cylinder sides, sphere meridians (a multiple of 4)
constexpr int n_latitudes = 9;     // sphere: points pole to pole, odd (an equator)
constexpr double min_stick = 1e-3; // m: shorter segments are not drawn

multibody::SE3 to_se3(const urdf::Pose& pose) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  const Eigen::Quaterniond q(w, x, y, z);
  return multibody::SE3(q.normalized().toRotationMatrix(),
                        Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z));
}

/// vtkCylinderSource's axis is its y: this turns it onto z (rotation of +90 deg about x).
multibody::SE3 y_to_z() {
  return multibody::SE3(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                        Eigen::Vector3d::Zero());
}

/// A shape of kind @p kind on @p body with the polygons of @p surface, whose points x are
/// moved to @p to_body (diag(@p scale) x) in body coordinates. Returns false if @p surface has no
/// polygon.
bool append_surface(vtkPolyData& surface, LinkShape::Kind kind, int body, const std::string& source,
                    const multibody::SE3& to_body, const Eigen::Vector3d& scale,
                    std::vector<LinkShape>& shapes) {
  vtkCellArray* polys = surface.GetPolys();
  if (!polys || polys->GetNumberOfCells() == 0)
    return false;
  LinkShape shape;
  shape.kind = kind;
  shape.body = body;
  shape.source = source;
  // The polygons' points, exact duplicates merged (vtkCubeSource and vtkCylinderSource repeat
  // edge points for their normals): a box has 8 points instead of 24, a cylinder 32, not 64.
  std::map<std::array<double, 3>, int> index_of;
  std::vector<Eigen::Vector3d> points;
  shape.offsets.push_back(0);
  vtkNew<vtkIdList> ids;
  polys->InitTraversal();
  while (polys->GetNextCell(ids)) {
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      std::array<double, 3> x;
      surface.GetPoint(ids->GetId(k), x.data());
      const auto [it, added] = index_of.emplace(x, static_cast<int>(points.size()));
      if (added)
        points.push_back(to_body.act_point(scale.cwiseProduct(Eigen::Vector3d(x[0], x[1], x[2]))));
      shape.connectivity.push_back(it->second);
    }
    shape.offsets.push_back(static_cast<int>(shape.connectivity.size()));
  }
  shape.points.resize(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    shape.points.col(static_cast<Eigen::Index>(i)) = points[i];
  shapes.push_back(std::move(shape));
  return true;
}

/// Collects the text of VTK error and warning events (which then are not printed): of VTK's
/// "ERROR: In file, line n\nclass (address): text\n\n" only the text.
class MessageCollector : public vtkCommand {
public:
  static MessageCollector* New() { return new MessageCollector; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    if (!data)
      return;
    std::string text = static_cast<const char*>(data);
    if (const auto colon = text.find("): "); colon != std::string::npos)
      text = text.substr(colon + 3);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())))
      text.pop_back();
    messages += (messages.empty() ? "" : "; ") + text;
  }
  std::string messages;
};

/// The surface of the mesh file @p filename (URDF <mesh filename>) of link @p link.
vtkSmartPointer<vtkPolyData> read_mesh(const std::filesystem::path& urdf_file,
                                       const std::string& link, const std::string& filename) {
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(urdf_file.string() + ": link '" + link + "': mesh '" + filename +
                             "': " + what);
  };
  if (filename.rfind("package://", 0) == 0)
    fail("package:// URIs need ROS to resolve; use a path relative to the URDF's directory");
  std::filesystem::path path = filename.rfind("file://", 0) == 0 ? filename.substr(7) : filename;
  if (path.empty())
    fail("empty file name");
  if (path.is_relative())
    path = urdf_file.parent_path() / path;
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  vtkSmartPointer<vtkAlgorithm> reader;
  if (extension == ".stl") {
    auto stl = vtkSmartPointer<vtkSTLReader>::New();
    stl->SetFileName(path.c_str());
    reader = stl;
  } else if (extension == ".obj") {
    auto obj = vtkSmartPointer<vtkOBJReader>::New();
    obj->SetFileName(path.c_str());
    reader = obj;
  } else if (extension == ".ply") {
    auto ply = vtkSmartPointer<vtkPLYReader>::New();
    ply->SetFileName(path.c_str());
    reader = ply;
  } else {
    fail("unsupported extension '" + extension + "' (.stl, .obj and .ply are read)");
  }
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    fail("no such file '" + path.string() + "'");
  if (!std::ifstream(path, std::ios::binary))
    fail("cannot read '" + path.string() + "'");
  // Errors fail (with the warnings before them); warnings alone do not, and are not printed.
  vtkNew<MessageCollector> messages, errors, pipeline; // pipeline: the executive's "failure"
  reader->AddObserver(vtkCommand::ErrorEvent, messages);
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline);
  reader->Update();
  auto* surface = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0));
  if (!errors->messages.empty() || !pipeline->messages.empty() || reader->GetErrorCode() != 0)
    fail("VTK could not read '" + path.string() +
         "': " + (messages->messages.empty() ? pipeline->messages : messages->messages));
  if (!surface || surface->GetNumberOfPoints() == 0 || surface->GetNumberOfPolys() == 0)
    fail("'" + path.string() + "' has no polygons");
  return surface;
}

/// Appends the surface of @p geometry at @p origin (link frame) of the link of @p frame, on
/// its body; mesh files are found from @p urdf_file.
void add_geometry(const urdf::Geometry& geometry, const urdf::Pose& origin,
                  const multibody::Frame& frame, const std::filesystem::path& urdf_file,
                  std::vector<LinkShape>& shapes) {
  const multibody::SE3 placement = frame.placement * to_se3(origin);
  const Eigen::Vector3d one = Eigen::Vector3d::Ones();
  bool added = false;
  switch (geometry.type) {
  case urdf::Geometry::BOX: {
    const auto& box = static_cast<const urdf::Box&>(geometry);
    vtkNew<vtkCubeSource> source;
    source->SetXLength(box.dim.x);
    source->SetYLength(box.dim.y);
    source->SetZLength(box.dim.z);
    source->Update();
    added = append_surface(*source->GetOutput(), LinkShape::Kind::box, frame.body, frame.name,
                           placement, one, shapes);
    break;
  }
  case urdf::Geometry::CYLINDER: {
    const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
    vtkNew<vtkCylinderSource> source;
    source->SetRadius(cylinder.radius);
    source->SetHeight(cylinder.length);
    source->SetResolution(n_sides);
    source->CappingOn();
    source->Update();
    added = append_surface(*source->GetOutput(), LinkShape::Kind::cylinder, frame.body, frame.name,
                           placement * y_to_z(), one, shapes);
    break;
  }
  case urdf::Geometry::SPHERE: {
    vtkNew<vtkSphereSource> source;
    source->SetRadius(static_cast<const urdf::Sphere&>(geometry).radius);
    source->SetThetaResolution(n_sides);
    source->SetPhiResolution(n_latitudes);
    source->Update();
    added = append_surface(*source->GetOutput(), LinkShape::Kind::sphere, frame.body, frame.name,
                           placement, one, shapes);
    break;
  }
  case urdf::Geometry::MESH: {
    const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
    const auto surface = read_mesh(urdf_file, frame.name, mesh.filename);
    added = append_surface(*surface, LinkShape::Kind::mesh, frame.body, frame.name, placement,
                           Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z), shapes);
    break;
  }
  }
  if (!added)
    throw std::runtime_error(urdf_file.string() + ": link '" + frame.name +
                             "': geometry without polygons");
}

/// A cylinder of radius @p radius on body @p body from @p a to @p b (body coordinates), towards
/// the joint or frame @p name.
void add_stick(int body, const std::string& name, const Eigen::Vector3d& a,
               const Eigen::Vector3d& b, double radius, std::vector<LinkShape>& shapes) {
  const Eigen::Vector3d axis = b - a;
  const double length = axis.norm();
  if (length < min_stick)
    return;
  const multibody::SE3 placement(
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix(),
      0.5 * (a + b));
  vtkNew<vtkCylinderSource> source;
  source->SetRadius(radius);
  source->SetHeight(length);
  source->SetResolution(n_sides);
  source->CappingOn();
  source->Update();
  append_surface(*source->GetOutput(), LinkShape::Kind::stick, body, name, placement * y_to_z(),
                 Eigen::Vector3d::Ones(), shapes);
}

} // namespace

std::vector<LinkShape> make_link_shapes(const multibody::Model& model,
                                        const std::filesystem::path& urdf_file,
                                        double stick_radius) {
  if (!(stick_radius > 0)) {
    std::ostringstream msg;
    msg << "Output/VTK stick radius = " << stick_radius << ": must be > 0 (m)";
    throw std::invalid_argument(msg.str());
  }
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDFFile(urdf_file.string());
  if (!urdf)
    throw std::runtime_error(urdf_file.string() + ": urdfdom could not parse the URDF file");
  std::vector<LinkShape> shapes;
  std::vector<bool> has_geometry(model.n_bodies, false);
  for (const multibody::Frame& frame : model.frames) {
    const auto link = urdf->getLink(frame.name);
    if (!link)
      continue;
    const std::size_t before = shapes.size();
    for (const auto& visual : link->visual_array)
      if (visual && visual->geometry)
        add_geometry(*visual->geometry, visual->origin, frame, urdf_file, shapes);
    if (shapes.size() == before)
      for (const auto& collision : link->collision_array)
        if (collision && collision->geometry)
          add_geometry(*collision->geometry, collision->origin, frame, urdf_file, shapes);
    if (shapes.size() > before)
      has_geometry[frame.body] = true;
  }
  // Sticks for bodies without geometry: to each child joint origin and each merged frame.
  for (int i = 2; i < model.n_bodies; ++i) {
    const int p = model.parent[i];
    if (p >= 1 && !has_geometry[p])
      add_stick(p, model.joint_names[i], Eigen::Vector3d::Zero(),
                model.joint_placement[i].translation, stick_radius, shapes);
  }
  for (const multibody::Frame& frame : model.frames)
    if (frame.body >= 1 && !has_geometry[frame.body])
      add_stick(frame.body, frame.name, Eigen::Vector3d::Zero(), frame.placement.translation,
                stick_radius, shapes);
  return shapes;
}

void write_links_vtp(const multibody::Model& model, const multibody::Data& data,
                     const std::vector<LinkShape>& shapes, const std::filesystem::path& path) {
  vtkIdType n_points = model.n_bodies - 1, n_polygons = 0, n_ids = 0;
  for (const LinkShape& shape : shapes) {
    n_points += shape.points.cols();
    n_polygons += shape.n_polygons();
    n_ids += static_cast<vtkIdType>(shape.connectivity.size());
  }
  vtkNew<vtkPoints> points; // Float32
  points->SetNumberOfPoints(n_points);
  vtkNew<vtkIntArray> body;
  body->SetName("body");
  body->SetNumberOfTuples(model.n_bodies - 1 + n_polygons);
  vtkNew<vtkTypeInt32Array> vertex_offsets, vertex_ids, offsets, ids;
  vertex_offsets->SetNumberOfTuples(model.n_bodies);
  vertex_ids->SetNumberOfTuples(model.n_bodies - 1);
  offsets->SetNumberOfTuples(n_polygons + 1);
  ids->SetNumberOfTuples(n_ids);
  // One vertex per body at its origin: point i - 1, cell i - 1.
  vertex_offsets->SetValue(0, 0);
  for (int i = 1; i < model.n_bodies; ++i) {
    const Eigen::Vector3d& x = data.oMi[i].translation;
    points->SetPoint(i - 1, x.x(), x.y(), x.z());
    vertex_ids->SetValue(i - 1, i - 1);
    vertex_offsets->SetValue(i, i);
    body->SetValue(i - 1, i);
  }
  vtkIdType point = model.n_bodies - 1, polygon = 0, id = 0;
  offsets->SetValue(0, 0);
  for (const LinkShape& shape : shapes) {
    const multibody::SE3& placement = data.oMi[shape.body];
    const vtkIdType first = point;
    for (Eigen::Index k = 0; k < shape.points.cols(); ++k, ++point) {
      const Eigen::Vector3d x = placement.act_point(shape.points.col(k));
      points->SetPoint(point, x.x(), x.y(), x.z());
    }
    for (int c : shape.connectivity)
      ids->SetValue(id++, first + c);
    const vtkIdType start = offsets->GetValue(polygon);
    for (int k = 1; k <= shape.n_polygons(); ++k) {
      offsets->SetValue(polygon + k, start + shape.offsets[k]);
      body->SetValue(model.n_bodies - 2 + polygon + k, shape.body);
    }
    polygon += shape.n_polygons();
  }
  vtkNew<vtkCellArray> vertices, polygons;
  vertices->SetData(vertex_offsets, vertex_ids);
  polygons->SetData(offsets, ids);
  vtkNew<vtkPolyData> links;
  links->SetPoints(points);
  links->SetVerts(vertices);
  links->SetPolys(polygons);
  links->GetCellData()->AddArray(body);
  links->GetCellData()->SetActiveScalars("body");

  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(links);
  writer->SetDataModeToAppended(); // raw binary after the XML header (no base64)
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  writer->SetCompressionLevel(1); // fastest; 9 gains < 1 % (coordinates hardly compress)
  writer->SetWriteToOutputString(true);
  if (!writer->Write())
    throw std::runtime_error("VTK could not write the links to '" + path.string() + "'");
  const std::string text = writer->GetOutputString();
  fem::write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

} // namespace plantar::app
