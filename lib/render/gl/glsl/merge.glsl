## The children at [at], composited in order into `merged` (a statement
## block shared by the filters; its caller names the point `at`).
    vec4 merged = vec4(0.0);
% for name in child_textures:
%     if loop.first:
    merged = texture(${name}, at);
%     else:
    merged = composite_${composite}(texture(${name}, at), merged);
%     endif
% endfor
