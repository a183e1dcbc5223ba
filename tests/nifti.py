"""Reading and writing NIfTI-1 volumes (.nii.gz) for the tests that make CT files themselves,
with numpy only: the header's fields are kept, the voxel array and the voxel-to-world map
(qform and sform, both in NIfTI's RAS frame; ITK and softface work in LPS) can be replaced."""
import gzip, struct
import numpy as np

DTYPES = {2: np.uint8, 4: np.int16, 8: np.int32, 16: np.float32, 64: np.float64, 512: np.uint16}


def read(filename):
    """(header bytes, voxels as an array indexed [k, j, i], the 4 x 4 voxel-to-RAS matrix)."""
    data = gzip.open(filename).read()
    header = bytearray(data[:348])
    dims = struct.unpack("<8h", header[40:56])
    dtype = DTYPES[struct.unpack("<h", header[70:72])[0]]
    offset = int(struct.unpack("<f", header[108:112])[0])
    shape = dims[3:0:-1]
    voxels = np.frombuffer(data[offset:offset + int(np.prod(shape)) * np.dtype(dtype).itemsize],
                           dtype=dtype).reshape(shape)
    affine = np.eye(4)
    affine[:3, :] = np.array(struct.unpack("<12f", header[280:328])).reshape(3, 4)
    return header, voxels, affine


def write(filename, header, voxels, affine):
    """The volume with @p voxels ([k, j, i]) and the voxel-to-RAS map @p affine, which must be a
    signed permutation of the axes times the voxel sizes (as NIfTI's qform can say)."""
    header = bytearray(header)
    nk, nj, ni = voxels.shape
    header[40:56] = struct.pack("<8h", 3, ni, nj, nk, 1, 1, 1, 1)
    spacing = np.linalg.norm(affine[:3, :3], axis=0)
    rotation = affine[:3, :3] / spacing
    qfac = 1.0 if np.linalg.det(rotation) > 0 else -1.0
    if qfac < 0:
        rotation[:, 2] *= -1
    header[76:92] = struct.pack("<4f", qfac, *spacing)
    # The rotation as NIfTI's quaternion (b, c, d; a >= 0).
    w = np.sqrt(max(0.0, 1.0 + np.trace(rotation))) / 2
    if w > 1e-6:
        b = (rotation[2, 1] - rotation[1, 2]) / (4 * w)
        c = (rotation[0, 2] - rotation[2, 0]) / (4 * w)
        d = (rotation[1, 0] - rotation[0, 1]) / (4 * w)
    else:          # a half turn: the axis from the diagonal
        b, c, d = np.sqrt(np.maximum(0.0, (np.diag(rotation) + 1) / 2))
        if b > 0.5:
            c, d = np.sign(rotation[0, 1]) * c, np.sign(rotation[0, 2]) * d
        elif c > 0.5:
            d = np.sign(rotation[1, 2]) * d
    header[256:280] = struct.pack("<6f", b, c, d, *affine[:3, 3])
    header[280:328] = struct.pack("<12f", *affine[:3, :].ravel())
    header[108:112] = struct.pack("<f", 352.0)
    with gzip.open(filename, "wb") as out:
        out.write(bytes(header) + b"\0\0\0\0" + np.ascontiguousarray(voxels).tobytes())
