function write_obj(path, v, f)
% Writes vertices v (n x 3) and triangles f (m x 3, 1-based) as an OBJ file.
fid = fopen(path, 'w');
if fid < 0, error('cannot write %s', path); end
fprintf(fid, 'v %.17g %.17g %.17g\n', v.');
fprintf(fid, 'f %d %d %d\n', f.');
fclose(fid);
end
