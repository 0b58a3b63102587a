import struct

from pkgforge.scaffold.stl import binary_stl, box_triangles


def test_box_is_a_valid_binary_stl():
    data = binary_stl(box_triangles((0.1, 0.2, 0.3)), header="solid would confuse readers")
    assert not data.startswith(b"solid")
    (count,) = struct.unpack_from("<I", data, 80)
    assert count == 12
    assert len(data) == 84 + 50 * count


def test_box_normals_point_outwards():
    for normal, a, b, c in box_triangles((1.0, 1.0, 1.0)):
        # the right-hand winding of (a, b, c) must agree with the stored normal
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        assert sum(cross[i] * normal[i] for i in range(3)) > 0
