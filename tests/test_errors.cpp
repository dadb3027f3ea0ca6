// The exception classes of error.h: each failure of the library is thrown as
// the subclass of its kind, catchable as that class, as its group and as
// Error with kind() set.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <type_traits>
#include <typeinfo>

#include "foldfill/error.h"
#include "foldfill/fill.h"
#include "foldfill/holes.h"
#include "foldfill/io.h"
#include "test_support.h"

namespace foldfill {
namespace {

// What a call threw: whether it was exactly `Expected`, its kind and message.
struct Thrown {
  bool exact = false;
  ErrorKind kind = ErrorKind::Internal;
  std::string what;
};

// Runs `call`, which must throw `Expected`; fails the test otherwise.
template <class Expected, class Call>
Thrown thrown_by(Call&& call) {
  static_assert(std::is_base_of_v<Error, Expected>);
  Thrown thrown;
  try {
    call();
    ADD_FAILURE() << "nothing was thrown, expected " << typeid(Expected).name();
  } catch (const Expected& e) {
    thrown.exact = typeid(e) == typeid(Expected);
    thrown.kind = e.kind();
    thrown.what = e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << typeid(e).name() << " was thrown (" << e.what() << "), expected "
                  << typeid(Expected).name();
  }
  return thrown;
}

// A 3 x 3 grid of unit squares in z = 0 without its middle one: one hole
// (loop 1) inside the outer edge (loop 0).
Mesh grid_with_hole() {
  Mesh mesh;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) mesh.positions.push_back({double(i), double(j), 0.0});
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;
      const int a = j * 4 + i, b = a + 1, c = a + 5, d = a + 4;
      mesh.faces.push_back({a, b, c});
      mesh.faces.push_back({a, c, d});
    }
  }
  return mesh;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = (testing::scratch_dir("errors") / name).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

TEST(Errors, ClassesAreNotConstructibleWithAnotherKind) {
  // Error itself takes no kind from outside: the class says the kind.
  static_assert(!std::is_constructible_v<Error, ErrorKind, std::string>);
  static_assert(!std::is_constructible_v<InputError, ErrorKind, std::string>);
  static_assert(std::is_base_of_v<InputError, BadFormatError>);
  static_assert(std::is_base_of_v<InputError, NonFiniteCoordinateError>);
  static_assert(std::is_base_of_v<InputError, BadFaceError>);
  static_assert(std::is_base_of_v<InputError, NonManifoldError>);
  static_assert(std::is_base_of_v<InputError, NotADiskError>);
  static_assert(!std::is_base_of_v<InputError, UsageError>);
  static_assert(!std::is_base_of_v<InputError, CannotReadError>);
  static_assert(!std::is_base_of_v<InputError, FillFailedError>);
  static_assert(std::is_base_of_v<std::runtime_error, Error>);
  EXPECT_EQ(UsageError("u").kind(), ErrorKind::Usage);
  EXPECT_EQ(CannotReadError("r").kind(), ErrorKind::CannotRead);
  EXPECT_EQ(BadFormatError("f").kind(), ErrorKind::BadFormat);
  EXPECT_EQ(NonFiniteCoordinateError("n").kind(), ErrorKind::NonFiniteCoordinate);
  EXPECT_EQ(BadFaceError("b").kind(), ErrorKind::BadFace);
  EXPECT_EQ(NonManifoldError("m").kind(), ErrorKind::NonManifold);
  EXPECT_EQ(NotADiskError("d").kind(), ErrorKind::NotADisk);
  EXPECT_EQ(FillFailedError("x").kind(), ErrorKind::FillFailed);
  EXPECT_EQ(CannotWriteError("w").kind(), ErrorKind::CannotWrite);
  EXPECT_EQ(InternalError("i").kind(), ErrorKind::Internal);
}

TEST(Errors, ThrowErrorThrowsTheClassOfTheKind) {
  const auto check = [](auto expected, ErrorKind kind) {
    using Expected = decltype(expected);
    const Thrown thrown = thrown_by<Expected>([&] { throw_error(kind, "SOURCE: problem"); });
    EXPECT_TRUE(thrown.exact) << to_string(kind);
    EXPECT_EQ(thrown.kind, kind) << to_string(kind);
    EXPECT_EQ(thrown.what, "SOURCE: problem");
  };
  check(UsageError(""), ErrorKind::Usage);
  check(CannotReadError(""), ErrorKind::CannotRead);
  check(BadFormatError(""), ErrorKind::BadFormat);
  check(NonFiniteCoordinateError(""), ErrorKind::NonFiniteCoordinate);
  check(BadFaceError(""), ErrorKind::BadFace);
  check(NonManifoldError(""), ErrorKind::NonManifold);
  check(NotADiskError(""), ErrorKind::NotADisk);
  check(FillFailedError(""), ErrorKind::FillFailed);
  check(CannotWriteError(""), ErrorKind::CannotWrite);
  check(InternalError(""), ErrorKind::Internal);
}

TEST(Errors, MissingFileIsCannotRead) {
  const std::string path = (testing::scratch_dir("errors") / "missing.obj").string();
  const Thrown thrown = thrown_by<CannotReadError>([&] { read_mesh(path); });
  EXPECT_TRUE(thrown.exact);
  EXPECT_EQ(thrown.what.rfind(path + ": cannot open", 0), 0u) << thrown.what;
  // Caught as the base class, the kind says the same.
  try {
    read_mesh(path);
    ADD_FAILURE() << "nothing was thrown";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::CannotRead);
    EXPECT_NE(dynamic_cast<const CannotReadError*>(&e), nullptr);
    EXPECT_EQ(dynamic_cast<const InputError*>(&e), nullptr);
  }
}

TEST(Errors, GarbageFileIsBadFormat) {
  const std::string path = write_file("garbage.obj", "hello world\n");
  const Thrown thrown = thrown_by<BadFormatError>([&] { read_mesh(path); });
  EXPECT_TRUE(thrown.exact);
  EXPECT_EQ(thrown.kind, ErrorKind::BadFormat);
  EXPECT_EQ(thrown.what.rfind(path + ": ", 0), 0u) << thrown.what;
  // A binary format's garbage too, and both are InputErrors.
  const std::string ply = write_file("garbage.ply", std::string("\x01\x02garbage", 9));
  EXPECT_EQ(thrown_by<InputError>([&] { read_mesh(ply); }).kind, ErrorKind::BadFormat);
}

TEST(Errors, BadContentIsItsInputError) {
  const Thrown nan = thrown_by<NonFiniteCoordinateError>(
      [] { parse_mesh("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj, "nan.obj"); });
  EXPECT_TRUE(nan.exact);
  EXPECT_EQ(nan.kind, ErrorKind::NonFiniteCoordinate);

  const Thrown face = thrown_by<BadFaceError>(
      [] { parse_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", MeshFormat::Obj, "face.obj"); });
  EXPECT_TRUE(face.exact);
  EXPECT_EQ(face.kind, ErrorKind::BadFace);

  Mesh repeated = grid_with_hole();
  repeated.faces[0] = {0, 1, 1};
  EXPECT_TRUE(thrown_by<BadFaceError>([&] { validate_mesh(repeated); }).exact);
}

TEST(Errors, UnknownExtensionIsUsage) {
  const Thrown thrown = thrown_by<UsageError>([] { format_from_path("mesh.txt"); });
  EXPECT_TRUE(thrown.exact);
  EXPECT_EQ(thrown.kind, ErrorKind::Usage);
}

TEST(Errors, UnwritableOutputIsCannotWrite) {
  const std::string path = (testing::scratch_dir("errors") / "no_folder" / "out.obj").string();
  const Thrown thrown = thrown_by<CannotWriteError>([&] { write_mesh(grid_with_hole(), path); });
  EXPECT_TRUE(thrown.exact);
  EXPECT_EQ(thrown.kind, ErrorKind::CannotWrite);
}

TEST(Errors, FillingANonManifoldMeshIsNonManifold) {
  // Three faces on the edge 0-1.
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  mesh.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  FillRequest request;
  request.source = "fan.obj";
  const Thrown thrown = thrown_by<NonManifoldError>([&] { fill(mesh, request); });
  EXPECT_TRUE(thrown.exact);
  EXPECT_EQ(thrown.kind, ErrorKind::NonManifold);
  EXPECT_EQ(thrown.what.rfind("fan.obj: ", 0), 0u) << thrown.what;
}

TEST(Errors, NamingALoopThatIsNotADiskIsNotADisk) {
  // Two triangles that share only vertex 0: both loops touch there.
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-2, 0, 0}, {0, -2, 0}};
  mesh.faces = {{0, 1, 2}, {0, 3, 4}};
  FillRequest request;
  request.selection.mode = HoleSelection::Mode::Ids;
  request.selection.ids = {0};
  const Thrown thrown = thrown_by<NotADiskError>([&] { fill(mesh, request); });
  EXPECT_TRUE(thrown.exact);
  EXPECT_EQ(thrown.kind, ErrorKind::NotADisk);
}

TEST(Errors, BadFillRequestIsUsage) {
  const Mesh mesh = grid_with_hole();
  // An id that names no loop.
  FillRequest unknown_id;
  unknown_id.selection.mode = HoleSelection::Mode::Ids;
  unknown_id.selection.ids = {7};
  const Thrown id = thrown_by<UsageError>([&] { fill(mesh, unknown_id); });
  EXPECT_TRUE(id.exact);
  EXPECT_NE(id.what.find("no loop with id 7"), std::string::npos) << id.what;

  // The prototype's weights with lambda set as well.
  FillRequest contradicting;
  contradicting.options.prototype = PrototypeWeights{};
  contradicting.options.energy.lambda = 2 * EnergyOptions{}.lambda + 1;
  const Thrown options = thrown_by<UsageError>([&] { fill(mesh, contradicting); });
  EXPECT_TRUE(options.exact);
  EXPECT_EQ(options.kind, ErrorKind::Usage);
  EXPECT_NE(options.what.find("prototype"), std::string::npos) << options.what;
}

}  // namespace
}  // namespace foldfill
