"""The inverses of a stack of square matrices that share a sparsity pattern, by their block
triangular form (numpy over the stack; the form found once per pattern).

The loads' equations of a mechanism with many loops are sparse: an N-four-bar's joint rows each
see the forces of one or two loops, and the square system of its 2N + 1 equations is, up to an
order of its rows and columns, block lower triangular with 2 × 2 diagonal blocks. Its inverse
then costs N small solves, O(m²) per matrix against O(m³) for a dense inverse (measured on the
shared machine, 200 samples of the 81 × 81 system of N = 40: ~40 ms dense).

The form (Duff and Reid's: a row for each column from a maximum matching, then the strongly
connected components of "column c's equation uses unknown d", in the order that puts every
unknown's dependencies first) depends only on which entries are non-zero at some sample. With
rows R_k, columns C_k of block k and D_k the earlier columns its rows use, the rows X[C_k] of
X = A⁻¹ are

    X[C_k] = A[R_k, C_k]⁻¹ (I[R_k] − A[R_k, D_k] X[D_k]),

a block forward substitution, which like a dense inverse is backward stable (the computed
inverse of a matrix near a singular one has a huge norm; :mod:`.loads_solve` relies on it).
Diagonal blocks of sizes 1 and 2 are inverted in closed form, every block of one size at once;
larger ones by LAPACK. A matrix without a perfect matching (structurally singular) gets NaN.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

Block = tuple[np.ndarray, np.ndarray, np.ndarray]
"""One diagonal block: its rows R_k, its columns C_k, the earlier columns D_k its rows use."""


def block_inverse(matrices: np.ndarray) -> np.ndarray:
    """The inverses (n, m, m) of the square ``matrices`` (n, m, m) (module docstring); NaN or
    inf where a matrix is singular."""
    n, m, _ = matrices.shape
    matrices = np.ascontiguousarray(matrices)  # np.take copies a strided array whole each time
    pattern = np.any(matrices != 0.0, axis=0)
    blocks = _blocks(pattern.tobytes(), m)
    if blocks is None:
        return np.full_like(matrices, np.nan)
    diagonal = _diagonal_inverses(matrices, blocks)
    inverse = np.zeros((n, m, m))
    with np.errstate(invalid="ignore", over="ignore"):  # a singular sample's NaN and inf
        for k, (rows, columns, earlier) in enumerate(blocks):
            rhs = np.zeros((n, rows.size, m))
            rhs[:, np.arange(rows.size), rows] = 1.0
            if earlier.size:
                used = np.take(np.take(matrices, rows, axis=1), earlier, axis=2)
                rhs -= used @ np.take(inverse, earlier, axis=1)
            inverse[:, columns, :] = diagonal[k] @ rhs
    return inverse


def _diagonal_inverses(matrices: np.ndarray, blocks: tuple[Block, ...]) -> list[np.ndarray]:
    """The inverses (n, b, b) of every diagonal block, those of one size at once."""
    out: list[np.ndarray] = [np.empty(0)] * len(blocks)
    sizes = np.array([rows.size for rows, _, _ in blocks])
    for size in np.unique(sizes):
        which = np.flatnonzero(sizes == size)
        rows = np.array([blocks[k][0] for k in which])  # (K, b)
        columns = np.array([blocks[k][1] for k in which])
        stack = matrices[:, rows[:, :, None], columns[:, None, :]]  # (n, K, b, b)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            inverses = _small_inverse(stack)
        for i, k in enumerate(which):
            out[k] = inverses[:, i]
    return out


def _small_inverse(stack: np.ndarray) -> np.ndarray:
    """Inverses of (..., b, b): closed form for b = 1 and 2 (the adjugate over the
    determinant), LAPACK for the others; NaN or inf where singular."""
    size = stack.shape[-1]
    if size == 1:
        return 1.0 / stack
    if size == 2:
        a, b, c, d = stack[..., 0, 0], stack[..., 0, 1], stack[..., 1, 0], stack[..., 1, 1]
        det = a * d - b * c
        return np.stack([np.stack([d, -b], -1), np.stack([-c, a], -1)], -2) / det[..., None, None]
    flat = stack.reshape(-1, size, size)
    try:
        return np.linalg.inv(flat).reshape(stack.shape)
    except np.linalg.LinAlgError:  # some matrix is exactly singular: the others one by one
        return np.array([_inverse_or_nan(matrix) for matrix in flat]).reshape(stack.shape)


def _inverse_or_nan(matrix: np.ndarray) -> np.ndarray:
    try:
        return np.linalg.inv(matrix)
    except np.linalg.LinAlgError:
        return np.full_like(matrix, np.nan)


@lru_cache(maxsize=64)
def _blocks(pattern: bytes, m: int) -> tuple[Block, ...] | None:
    """The block triangular form (module docstring) of the non-zero ``pattern`` (m × m bool,
    as bytes), blocks in solve order; None without a perfect matching."""
    nonzero = np.frombuffer(pattern, dtype=bool).reshape(m, m)
    uses = [np.flatnonzero(nonzero[r]).tolist() for r in range(m)]
    row_of = _matching(uses, m)
    if row_of is None:
        return None
    depends = [[d for d in uses[row_of[c]] if d != c] for c in range(m)]
    blocks = []
    for component in _components(depends):
        columns = np.array(sorted(component))
        rows = np.array([row_of[c] for c in columns])
        earlier = np.flatnonzero(nonzero[rows].any(axis=0))
        blocks.append((rows, columns, np.setdiff1d(earlier, columns)))
    return tuple(blocks)


def _matching(uses: list[list[int]], m: int) -> list[int] | None:
    """A row for every column (row_of[c]) such that row row_of[c] uses column c, one augmenting
    path (breadth first) per row; None when there is none (a structurally singular matrix)."""
    row_of, column_of = [-1] * m, [-1] * m
    for start in range(m):
        reached_from: dict[int, int] = {}  # column → the row whose equation reached it
        queue, free = [start], -1
        for row in queue:  # the queue grows while it is read
            for column in uses[row]:
                if column not in reached_from:
                    reached_from[column] = row
                    if row_of[column] < 0:
                        free = column
                        break
                    queue.append(row_of[column])
            if free >= 0:
                break
        if free < 0:
            return None
        column = free
        while column >= 0:  # flip the path back to the start
            row = reached_from[column]
            previous = column_of[row]  # -1 for the start row
            row_of[column], column_of[row] = row, column
            column = previous
    return row_of


def _components(depends: list[list[int]]) -> list[list[int]]:
    """The strongly connected components of the graph c → d (d in depends[c]), each after every
    component it reaches (Tarjan's order: dependencies first); iterative."""
    count = len(depends)
    index, low = [-1] * count, [0] * count
    on_stack, stack, out = [False] * count, [], []
    counter = 0
    for root in range(count):
        if index[root] >= 0:
            continue
        work = [(root, 0)]
        while work:
            node, i = work.pop()
            if i == 0:
                index[node] = low[node] = counter
                counter += 1
                stack.append(node)
                on_stack[node] = True
            if i < len(depends[node]):
                work.append((node, i + 1))
                child = depends[node][i]
                if index[child] < 0:
                    work.append((child, 0))
                elif on_stack[child]:
                    low[node] = min(low[node], index[child])
                continue
            if low[node] == index[node]:
                component = []
                while True:
                    top = stack.pop()
                    on_stack[top] = False
                    component.append(top)
                    if top == node:
                        break
                out.append(component)
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
    return out
