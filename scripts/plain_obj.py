"""Vertex and face lists of an OBJ file, as the scripts here compare them (positions as
written, faces as 0-based corner lists; texture and normal indices ignored)."""


def read_obj(path):
    positions, faces = [], []
    with open(path, encoding="utf-8") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                positions.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                faces.append([int(p.split("/")[0]) - 1 for p in parts[1:]])
    return positions, faces
