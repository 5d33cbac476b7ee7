function va = vertexAttachments(tr, vi)
% Stand-in for MATLAB's triangulation/vertexAttachments, which Octave lacks.
% For each vertex c in vi, the faces of tr (the triangulation stand-in's
% struct) that contain c, in order around c along the faces' orientation:
% the next face shares the edge from c to the current face's corner before c.
% At a boundary vertex the fan starts at the face with the boundary edge
% leaving c. The reference code's compute_vertex_ring builds ordered vertex
% rings from this order.
f = tr.ConnectivityList;
va = cell(numel(vi), 1);
for i = 1:numel(vi)
  c = vi(i);
  [fs, pos] = find(f == c);
  k = numel(fs);
  nxt = f(sub2ind(size(f), fs, mod(pos, 3) + 1));      % corner after c
  prv = f(sub2ind(size(f), fs, mod(pos + 1, 3) + 1));  % corner before c
  start = find(~ismember(nxt, prv), 1);
  if isempty(start), start = 1; end
  order = zeros(1, k);
  order(1) = start;
  for j = 2:k
    s = find(nxt == prv(order(j - 1)), 1);
    if isempty(s), order = order(1:j - 1); break; end
    order(j) = s;
  end
  va{i} = fs(order).';
end
end
